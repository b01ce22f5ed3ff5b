#!/usr/bin/env bash
# Re-approves the golden images of tests/golden_test.cpp: renders the real
# frame 21 with every filter at 320x180 into tests/golden/. Look at the images
# (and at `git diff --stat`) before committing them.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target meniscus_cli >/dev/null
in=tests/data/splishsplash/partio/ParticleData_Fluid_21.bgeo
for f in none gaussian bilateral binomial curvature-flow narrow-range; do
    build/meniscus render "$in" -o "tests/golden/frame21_$f.png" --width 320 --height 180 --filter "$f"
done
build/meniscus render "$in" -o tests/golden/frame21_narrow-range-1d.png --width 320 --height 180 \
    --filter narrow-range --separable
echo "approved: $(ls tests/golden/*.png | wc -l) images in tests/golden/"
