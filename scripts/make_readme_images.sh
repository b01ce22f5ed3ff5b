#!/usr/bin/env bash
# Re-renders the README's pictures (docs/images/) on the CPU backend, the
# reference: frame 21 of the 117,649-particle dam break at 640x360 with default
# settings, each debug view, every filter and every material; and the demo.
# Look at them before committing.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target meniscus_cli >/dev/null
in=data/dambreak_r0.01/ParticleData_Fluid_21.bgeo
render() { build/meniscus render "$in" -o "docs/images/$1.png" --width 640 --height 360 --backend cpu "${@:2}"; }
render dambreak21_final
for v in raw-depth depth normals thickness; do render "dambreak21_$v" --view "$v"; done
for f in none gaussian bilateral binomial curvature-flow narrow-range; do render "filter_$f" --filter "$f"; done
for m in murky milk lava sand; do render "material_$m" --material "$m"; done
build/meniscus demo -o docs/images/demo.png --width 640 --height 360 --backend cpu
