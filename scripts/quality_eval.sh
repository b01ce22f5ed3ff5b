#!/usr/bin/env bash
# Scores every depth filter against the true SPH iso-surface ray-traced by
# refsurf (see docs/quality.md). Usage: scripts/quality_eval.sh REFSURF_DIR [OUT_DIR]
# Assumes build/meniscus is built (Release), REFSURF_DIR/build/refsurf is built,
# and /usr/bin/python3 has numpy + OpenImageIO. Prints markdown tables, and
# writes error maps (scripts/error_map.py) of the MAPS rows into OUT_DIR.
# REFSURF_DIR (required): a copy of refsurf's source, the reference ray tracer
# of the true SPH surface, with build/refsurf built in it; refsurf is not part
# of this repository (docs/quality.md, Method).
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: scripts/quality_eval.sh REFSURF_DIR [OUT_DIR] (REFSURF_DIR: a copy of refsurf's source with build/refsurf built; see docs/quality.md)" >&2; exit 2; }
RS=$(cd "$1" && pwd); OUT=${2:-/tmp/meniscus_quality}; ROOT=$(cd "$(dirname "$0")/.." && pwd)
M=$ROOT/build/meniscus; W=640; H=360; FOV=40
mkdir -p "$OUT"
g++ -std=c++20 -O2 -I"$ROOT/include" "$ROOT/scripts/quality_to_raw.cpp" "$ROOT/build/libmeniscus_io.a" "$ROOT/build/libmeniscus_core.a" \
    $(pkg-config --libs OpenEXR tinyxml2 libpng zlib tbb) -o "$OUT/to_raw"
DAM=$ROOT/data/dambreak_r0.01/ParticleData_Fluid_21.bgeo
SMALL=$ROOT/tests/data/splishsplash/partio/ParticleData_Fluid_21.bgeo
# Auto cameras = what `meniscus render` picks with no --eye (fov 40, estimated radius).
read -r _ DAM_E DAM_T _ _ < <("$OUT/to_raw" "$DAM" "$OUT/dam.raw" $W $H)
read -r _ SM_E SM_T _ _ < <("$OUT/to_raw" "$SMALL" "$OUT/small.raw" $W $H)
# name  particles  radius  eye  target. Radius = volume-equivalent (see docs/quality.md).
DAM_R=${DAM_R:-0.0093}; SMALL_R=${SMALL_R:-0.025}
CAMS="dam_auto $DAM $DAM_R $DAM_E $DAM_T
dam_close $DAM $DAM_R 0.9,0.8,1.4 1.5,0.3,0.0
small_auto $SMALL $SMALL_R $SM_E $SM_T"
# EXTRA_CAMS=1 adds a grazing side view of the splashes and a far view.
[[ ${EXTRA_CAMS:-0} == 1 ]] && CAMS+="
dam_side $DAM $DAM_R 0.6,0.35,3.2 0.6,0.35,0.0
dam_far $DAM $DAM_R 5.5,4.2,6.2 0.3,0.4,0.0"
# FILTER[:ITERATIONS|:sep][@FLUID_SCALE][+an]; +an: with --anisotropy on (Yu & Turk's kernels; the
# default since 2026-12-05), else --anisotropy off; without :ITERATIONS the filter's default count
# (narrow-range: 1 since 2026-12-05; the tables of docs/quality.md were made with 3);
# FILTER raycast: --surface raycast (the SPH surface ray cast from the splat, no filter);
# a trailing -nofill: --fill-holes 0 (the hole filling is on by default since 2026-12-05).
# FILTERS="..." in the environment picks others.
FILTERS=${FILTERS:-"none gaussian bilateral binomial curvature-flow curvature-flow:40 curvature-flow:80 narrow-range narrow-range:sep narrow-range@0.5 narrow-range@0.25
none+an gaussian+an bilateral+an binomial+an curvature-flow+an narrow-range+an narrow-range:1+an narrow-range:sep+an narrow-range@0.5+an"}
while read -r NAME IN R E T; do
  RAW=$OUT/$( [[ $IN == "$DAM" ]] && echo dam || echo small ).raw
  echo "## $NAME: radius $R, eye $E, target $T, fov $FOV, ${W}x${H}"
  "$RS/build/refsurf" "$RAW" --out "$OUT/${NAME}_ref" --radius "$R" --eye "$E" --target "$T" \
      --fov $FOV --width $W --height $H >/dev/null
  echo "| filter | IoU | ref px | cand px | normal mean° | median° | p90° | depth abs rel | depth signed rel | abs / r | signed / r |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
  for F in $FILTERS; do
    G=${F%-nofill}; B=${G%+an}; ARGS=(--filter "${B%%[:@]*}"); [[ $B == *:sep* ]] && ARGS+=(--separable)
    [[ $B == raycast* ]] && ARGS=(--surface raycast)
    if [[ $G == *+an ]]; then ARGS+=(--anisotropy on); else ARGS+=(--anisotropy off); fi
    [[ $F == *-nofill ]] && ARGS+=(--fill-holes 0)
    [[ $B == *@* ]] && ARGS+=(--fluid-scale "${B##*@}")
    [[ $B == *:[0-9]* ]] && { I=${B##*:}; ARGS+=(--iterations "${I%%@*}"); }
    "$M" --threads 2 render "$IN" -o "$OUT/${NAME}_${F//[:@+]/_}.exr" "${ARGS[@]}" --background none \
        --radius "$R" --eye "$E" --target "$T" --fov $FOV --width $W --height $H 2>/dev/null
    /usr/bin/python3 "$RS/compare.py" "$OUT/${NAME}_ref" "$OUT/${NAME}_${F//[:@+]/_}.exr" | /usr/bin/python3 -c "
import json,sys; j=json.load(sys.stdin)
a,s,z=j['depth_mean_abs_rel'],j['depth_mean_signed_rel'],j['depth_median_ref']/$R
print('| $F | %.4f | %d | %d | %.2f | %.2f | %.2f | %.5f | %+.5f | %.2f | %+.2f |' % (j['iou'],j['ref_covered'],
  j['cand_covered'],j['normal_mean_deg'],j['normal_median_deg'],j['normal_p90_deg'],a,s,a*z,s*z))"
  done
  # Error maps (scripts/error_map.py) of the MAPS rows that were rendered.
  for F in ${MAPS:-narrow-range narrow-range:1+an}; do
    X=$OUT/${NAME}_${F//[:@+]/_}.exr
    [[ -f $X ]] && /usr/bin/python3 "$ROOT/scripts/error_map.py" "$OUT/${NAME}_ref" "$X" "$OUT/${NAME}_${F//[:@+]/_}_error.png"
  done
  echo
done <<< "$CAMS"
