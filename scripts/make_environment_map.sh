#!/usr/bin/env bash
# Writes the test environment map (tests/data/environment/sky_128x64.exr) with
# scripts/make_environment_map.cpp, compiled against OpenEXR.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
c++ -std=c++17 -O1 "$root/scripts/make_environment_map.cpp" -o "$tmp/make_environment_map" \
    $(pkg-config --cflags --libs OpenEXR)
mkdir -p "$root/tests/data/environment"
"$tmp/make_environment_map" "$root/tests/data/environment/sky_128x64.exr"
