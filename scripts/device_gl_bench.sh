#!/usr/bin/env bash
# The GL backend on a real GPU, for the table in docs/performance.md ("GL
# backend on a GPU (NVIDIA H200)"): run on a
# lent NVIDIA machine (no Debian packages there, nothing to install) over a
# bundle made here by scripts/make_device_bundle.sh. Prints the GPU, driver and
# the bench's lines, and writes CPU and GL renders of frame 21 (PNG + EXR) to
# $OUT for a parity check on that driver.
#   usage (on the device machine, from the repository root):
#     bash scripts/device_gl_bench.sh [BUNDLE]      # BUNDLE defaults to .devbundle
# The glvnd loaders come as Debian .debs in .gl/, unpacked below;
# NVIDIA's EGL vendor library is the driver's own.
set -uo pipefail
B=${1:-.devbundle}
OUT=${OUT:-/tmp/out}
mkdir -p "$OUT"
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$vendor" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv,noheader
grep PRETTY_NAME /etc/os-release
nproc
# The bundle's own libraries; its glibc only where the system's is older.
run() {
    local exe=$1
    shift
    if LD_LIBRARY_PATH="$B/lib" "$B/bin/$exe" --help >/dev/null 2>&1; then
        LD_LIBRARY_PATH="$B/lib" "$B/bin/$exe" "$@"
    else
        "$B/glibc/ld-linux-x86-64.so.2" --library-path "$B/lib:$B/glibc" "$B/bin/$exe" "$@"
    fi
}
frame=data/dambreak_r0.01/ParticleData_Fluid_21.bgeo
echo "== 1M particles (frame 21 tiled 3x3), 1920x1080, GL"
run bench "$frame" --tile 3 --no-mesh --backend gl --width 1920 --height 1080 \
    --filter narrow-range --filter curvature-flow --filter gaussian --filter none --separable --repeat 21
echo "== 1M particles, 1920x1080, GL, every AOV read back (an EXR)"
run bench "$frame" --tile 3 --no-mesh --backend gl --width 1920 --height 1080 \
    --filter narrow-range --all-aovs --repeat 11
echo "== frame 21 (117,649 particles), 1280x720, CPU (all cores) and GL"
run bench "$frame" --no-mesh --backend both --filter narrow-range --filter curvature-flow --separable --repeat 11
echo "== frame 21, 1280x720, GL, noise, whitening, spray, silhouette"
run bench "$frame" --no-mesh --backend gl --filter narrow-range --noise --whiten --spray --silhouette --repeat 11
echo "== 1M particles, 1920x1080, GL, noise, whitening, spray, silhouette"
run bench "$frame" --tile 3 --no-mesh --backend gl --width 1920 --height 1080 --filter narrow-range \
    --noise --whiten --spray --silhouette --repeat 11
# llvmpipe's settings on the GPU, for comparison: the driver's fills and
# copies, 16 row segments per invocation, read-back straight from the slots.
soft() { MENISCUS_GL_FILL=driver MENISCUS_GL_SEGMENT_ROUNDS=16 MENISCUS_GL_STAGED_READBACK=0 "$@"; }
echo "== 1M particles, 1920x1080, GL with llvmpipe's settings"
soft run bench "$frame" --tile 3 --no-mesh --backend gl --width 1920 --height 1080 \
    --filter narrow-range --filter none --repeat 11
echo "== renders for the parity check"
soft run meniscus render "$frame" --backend gl --width 1280 --height 720 -o "$OUT/frame21_gl_soft.exr"
for be in cpu gl; do
    run meniscus render "$frame" --backend "$be" --width 1280 --height 720 -o "$OUT/frame21_$be.png" || echo "render $be failed"
    run meniscus render "$frame" --backend "$be" --width 1280 --height 720 -o "$OUT/frame21_$be.exr" || echo "render $be exr failed"
done
cmp "$OUT/frame21_gl.exr" "$OUT/frame21_gl_soft.exr" && echo "GPU and llvmpipe settings: identical EXR"
for be in cpu gl; do
    run meniscus render "$frame" --backend "$be" --width 1280 --height 720 --noise --whiten --spray --silhouette \
        -o "$OUT/extras_$be.png" || echo "render $be extras failed"
done
rm -f "$OUT"/*.exr
ls -la "$OUT"
