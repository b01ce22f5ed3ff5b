#!/usr/bin/env bash
# Re-approves the golden images of tests/golden_test.cpp: renders the real
# frame 21 at 320x180 on the CPU backend (the reference) with every filter and
# every material, with the surface noise, the velocity whitening, the spray, the silhouette
# reduction, at half resolution and with two fluids (the frame with its
# `phase` attribute, tests/data/splishsplash/two_fluids/), into tests/golden/. Look at the images (and at
# `git diff --stat`) before committing them.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target meniscus_cli >/dev/null
in=tests/data/splishsplash/partio/ParticleData_Fluid_21.bgeo
render() { build/meniscus render "$in" -o "tests/golden/$1.png" --width 320 --height 180 --backend cpu "${@:2}"; }
for f in none gaussian bilateral binomial curvature-flow narrow-range; do
    render "frame21_$f" --filter "$f"
done
render frame21_narrow-range-1d --filter narrow-range --separable
for m in murky milk lava sand; do
    render "frame21_material_$m" --material "$m"
done
render frame21_noise --noise
render frame21_whiten --whiten
render frame21_spray --spray --spray-streak 0.03
render frame21_silhouette --silhouette --background none
render frame21_fluid-scale-0.5 --fluid-scale 0.5
build/meniscus render tests/data/splishsplash/two_fluids/ParticleData_Fluid_21_phase.bgeo \
    -o tests/golden/frame21_two_fluids.png --width 320 --height 180 --backend cpu \
    --fluid-attribute phase --material water,lava
echo "approved: $(ls tests/golden/*.png | wc -l) images in tests/golden/"
