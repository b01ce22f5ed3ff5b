#!/usr/bin/env bash
# Re-renders the pictures of the README and of the docs pages (docs/images/;
# most are in docs/features.md, "Pictures") on the CPU backend, the
# reference: frame 21 of the 117,649-particle dam break at 640x360 with default
# settings, each debug view, every filter and every material; the velocity
# whitening; the spray; the surface
# noise (a close view of frame 21, and frames 17-21 of the small dam break as a
# sequence, for the turbulence); two fluids (the small frame 21 split by its
# `phase` attribute, tests/data/splishsplash/two_fluids/); and the demo.
# Look at them before committing.
# MENISCUS_TESTDATA: the folder of the SPlisHSPlasH test runs that are not in
# this repository (it holds splishsplash/dambreak_r0.025_small/partio/, the
# small dam break, r = 0.025 m, all frames; a relative path is taken from the
# repository root). The noise-sequence and whitewater pictures need it; without
# it they are skipped, with a note.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target meniscus_cli >/dev/null
in=data/dambreak_r0.01/ParticleData_Fluid_21.bgeo
tank=tests/data/splishsplash_scene/scenes/DamBreakModel.json
render() { build/meniscus render "$in" -o "docs/images/$1.png" --width 640 --height 360 --backend cpu "${@:2}"; }
render dambreak21_final
for v in raw-depth depth normals thickness; do render "dambreak21_$v" --view "$v"; done
for f in none gaussian bilateral binomial curvature-flow narrow-range; do render "filter_$f" --filter "$f"; done
for m in murky milk lava sand; do render "material_$m" --material "$m"; done
close=(--eye 0.2,1.1,1.5 --target 1.3,0.35,0)
render whiten21 --whiten
render whiten21_map --whiten --view whitening
render spray21 --spray --spray-streak 0.03 "${close[@]}"
render spray21_cover --spray --spray-streak 0.03 --view spray "${close[@]}"
render silhouette21_off --background none "${close[@]}"
render silhouette21 --silhouette --background none "${close[@]}"
render silhouette21_map --silhouette --view silhouette "${close[@]}"
render anisotropy21_off "${close[@]}" --anisotropy off --iterations 3
render anisotropy21 "${close[@]}" --anisotropy on --iterations 1
build/meniscus render data/demo/ParticleData_Fluid_21.bgeo -o docs/images/anisotropy_demo_off.png --width 640 --height 360 --backend cpu --anisotropy off --iterations 3
build/meniscus render data/demo/ParticleData_Fluid_21.bgeo -o docs/images/anisotropy_demo.png --width 640 --height 360 --backend cpu --anisotropy on --iterations 1
render raycast21 "${close[@]}" --surface raycast
build/meniscus render data/demo/ParticleData_Fluid_21.bgeo -o docs/images/raycast_demo.png --width 640 --height 360 --backend cpu --surface raycast
render noise_close_off "${close[@]}"
render noise_close_on "${close[@]}" --noise
small=
if [ -n "${MENISCUS_TESTDATA:-}" ]; then
    small=$MENISCUS_TESTDATA/splishsplash/dambreak_r0.025_small/partio
    [ -d "$small" ] || { echo "make_readme_images.sh: $small not found (MENISCUS_TESTDATA must hold splishsplash/dambreak_r0.025_small/partio/)" >&2; exit 1; }
else
    echo "make_readme_images.sh: MENISCUS_TESTDATA not set: the noise-sequence and whitewater pictures are not re-rendered" >&2
fi
if [ -n "$small" ]; then
    seq=$(mktemp -d)
    for k in 17 18 19 20 21; do ln -s "$(realpath "$small/ParticleData_Fluid_$k.bgeo")" "$seq/"; done
    for v in final foam noise; do
        build/meniscus render "$seq/ParticleData_Fluid_*.bgeo" -o "$seq/${v}_%02d.png" --width 640 --height 360 \
            --backend cpu --noise --view "$v"
    done
    cp "$seq/final_21.png" docs/images/noise_sequence21.png
    cp "$seq/foam_21.png" docs/images/noise_sequence21_foam.png
    cp "$seq/noise_21.png" docs/images/noise_sequence21_noise.png
    rm -r "$seq"
    # Whitewater: frames 10-30 of the small dam break through `meniscus
    # whitewater`, frame 30 drawn with and without its diffuse layer.
    seq=$(mktemp -d)
    mkdir "$seq/in"
    for k in $(seq 10 30); do ln -s "$(realpath "$small/ParticleData_Fluid_$k.bgeo")" "$seq/in/"; done
    build/meniscus whitewater "$seq/in" -o "$seq/diffuse_%04d.bgeo" 2>/dev/null
    f30="$seq/in/ParticleData_Fluid_30.bgeo"
    build/meniscus render "$f30" -o docs/images/whitewater30_off.png --width 640 --height 360 --backend cpu
    build/meniscus render "$f30" -o docs/images/whitewater30.png --width 640 --height 360 --backend cpu \
        --diffuse "$seq/diffuse_%04d.bgeo" --spray-streak 0.03
    rm -r "$seq"
    # The block of frame 1 in its tank, and a close view of it: flat faces
    # refract the floor and walls without streaks.
    build/meniscus render "$small/ParticleData_Fluid_1.bgeo" -o docs/images/world_block1.png --width 640 --height 360 \
        --backend cpu --geometry "$tank"
    build/meniscus render "$small/ParticleData_Fluid_1.bgeo" -o docs/images/world_block1_close.png --width 640 \
        --height 360 --backend cpu --geometry "$tank" --eye -0.2,0.9,1.6 --target -1.2,0.45,0
fi
two=tests/data/splishsplash/two_fluids/ParticleData_Fluid_21_phase.bgeo
for v in final fluid-id; do
    build/meniscus render "$two" -o "docs/images/fluids21_$v.png" --width 640 --height 360 --backend cpu \
        --fluid-attribute phase --material water,murky --view "$v"
done
build/meniscus demo -o docs/images/demo.png --width 640 --height 360 --backend cpu
# The world around the liquid (docs/geometry.md): frame 21 in its tank, read
# from SPlisHSPlasH's own scene file (the walls toward the camera cut away);
# objects of the JSON form (an opaque ball, a metal box, a glass box); the
# glass scene simulated to 3 s and drawn with its glass.
render world_tank21 --geometry "$tank"
render world_objects21 --geometry '{"sphere": {"center": [-1.2, 0.22, 0.15], "radius": 0.16}, "material": {"color": [0.8, 0.25, 0.08], "roughness": 0.4}}' \
    --geometry '{"box": {"min": [0.55, 0, -0.7], "max": [0.85, 0.5, -0.4]}, "material": {"color": [0.95, 0.8, 0.5], "metalness": 1, "roughness": 0.2}}' \
    --geometry '{"box": {"min": [-2.05, 0, -0.8], "max": [-1.55, 0.7, 0.8]}, "material": {"glass": true}}'
# A mesh file's base colour map: the checker quad of tests/data/geometry
# (OBJ + MTL + PNG) stood up behind the liquid.
render world_texture21 --geometry '{"file": "tests/data/geometry/textured_quad.obj", "scale": [1.6, 1, 0.8], "rotate": {"axis": [1, 0, 0], "degrees": -90}, "translate": [-1.3, 0, -0.45]}'
# An environment map (the test map: a warm sky, a green ground band, a sun)
# for the background, the reflections of the liquid and of a chrome ball, and
# the ambient light (the floor's warm tint).
render world_environment21 --environment tests/data/environment/sky_128x64.exr --background floor --elevation 12 \
    --geometry '{"sphere": {"center": [-1.2, 0.3, 0.15], "radius": 0.2}, "material": {"color": [0.95, 0.95, 0.95], "metalness": 1, "roughness": 0.05}}'
# DualSPHysics' boundary particles (docs/geometry.md#dualsphysics-boundaries):
# frame 21 written as a DualSPHysics CSV inside an open tank of one layer of
# fixed boundary particles (scripts/make_dualsphysics_tank.py), drawn as walls
# (the default) and, for comparison, as the liquid.
dsph=$(mktemp -d)
build/meniscus convert "$in" "$dsph/fluid.ply" >/dev/null 2>&1
python3 scripts/make_dualsphysics_tank.py "$dsph/fluid.ply" "$dsph/PartCsv_0021.csv"
build/meniscus render "$dsph/PartCsv_0021.csv" --up 0,0,1 -o docs/images/dualsphysics_walls21.png --width 640 --height 360 --backend cpu
build/meniscus render "$dsph/PartCsv_0021.csv" --up 0,0,1 -o docs/images/dualsphysics_liquid21.png --width 640 --height 360 --backend cpu \
    --boundary-particles liquid
rm -r "$dsph"
glass=$(mktemp -d)
build/meniscus simulate scenes/glass.json --duration 3 -o "$glass/f_%04d.bgeo" --render "$glass/img_%04d.png" \
    --width 640 --height 360 --backend cpu 2>/dev/null
cp "$glass/img_0075.png" docs/images/world_glass.png
rm -r "$glass"
