#!/usr/bin/env bash
# Packs the Release bench and CLI with every shared library they load (glvnd's
# GL loaders excepted: those come from .gl/, the driver's EGL from the device)
# into .devbundle/, for scripts/device_gl_bench.sh on a lent GPU machine that
# has none of Debian's packages. glibc goes to .devbundle/glibc/, used only
# where the device's own is older than the one these were built against.
#   usage: cmake --build build --target bench meniscus_cli && bash scripts/make_device_bundle.sh
set -euo pipefail
cd "$(dirname "$0")/.."
B=.devbundle
rm -rf "$B"
mkdir -p "$B/bin" "$B/lib" "$B/glibc"
cp build/bench "$B/bin/bench"
cp build/meniscus "$B/bin/meniscus"
strip "$B/bin/"*
for exe in "$B/bin/"*; do
    ldd "$exe" | awk '/=> \//{print $3}'
done | sort -u | while read -r lib; do
    name=$(basename "$lib")
    case "$name" in
        libEGL.so*|libGL.so*|libGLX.so*|libOpenGL.so*|libGLdispatch.so*|libGLESv2.so*) ;;  # glvnd: from .gl/
        libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|ld-linux*) cp -L "$lib" "$B/glibc/$name" ;;
        *) cp -L "$lib" "$B/lib/$name" ;;
    esac
done
cp -L /lib64/ld-linux-x86-64.so.2 "$B/glibc/ld-linux-x86-64.so.2"
strip --strip-unneeded "$B/lib/"* 2>/dev/null || true
du -sh "$B"
