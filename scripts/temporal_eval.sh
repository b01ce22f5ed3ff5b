#!/usr/bin/env bash
# Temporal coherence: renders consecutive frames with one static camera (the
# first frame's automatic one), ray-traces the true SPH surface of each with
# refsurf, and scores per pixel how much our normals change from frame to frame
# against how much the true surface's do (scripts/temporal_score.py). Usage:
#   scripts/temporal_eval.sh REFSURF_DIR [OUT_DIR] [-- extra render options]
# FRAMES="a.bgeo b.bgeo ..." (default: the bundled data/demo frames 19-23, the
# small SPlisHSPlasH dam break, r = 0.025 m). Needs build/meniscus, REFSURF_DIR/
# build/refsurf, and /usr/bin/python3 with numpy + OpenImageIO (as quality_eval.sh).
# REFSURF_DIR (required): a copy of refsurf's source, the reference ray tracer
# of the true SPH surface, with build/refsurf built in it; refsurf is not part
# of this repository (docs/quality.md, Method).
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: scripts/temporal_eval.sh REFSURF_DIR [OUT_DIR] [-- extra render options] (REFSURF_DIR: a copy of refsurf's source with build/refsurf built; see docs/quality.md)" >&2; exit 2; }
RS=$(cd "$1" && pwd); shift
OUT=/tmp/meniscus_temporal
if [[ $# -gt 0 && $1 != -- ]]; then OUT=$1; shift; fi
[[ $# -gt 0 && $1 == -- ]] && shift
ROOT=$(cd "$(dirname "$0")/.." && pwd); M=$ROOT/build/meniscus; W=640; H=360; FOV=40
FRAMES=${FRAMES:-"$(ls "$ROOT"/data/demo/ParticleData_Fluid_*.bgeo | sort -V | tr '\n' ' ')"}
R=${R:-0.025}
mkdir -p "$OUT"
g++ -std=c++20 -O2 -I"$ROOT/include" "$ROOT/scripts/quality_to_raw.cpp" "$ROOT/build/libmeniscus_io.a" "$ROOT/build/libmeniscus_core.a" \
    $(pkg-config --libs OpenEXR tinyxml2 libpng zlib tbb) -o "$OUT/to_raw"
ARGS=(); K=0
for F in $FRAMES; do
  read -r _ E T _ _ < <("$OUT/to_raw" "$F" "$OUT/f$K.raw" $W $H)
  if [[ $K == 0 ]]; then EYE=$E; TARGET=$T; echo "camera: eye $EYE, target $TARGET, fov $FOV, ${W}x${H}, radius $R"; fi
  "$RS/build/refsurf" "$OUT/f$K.raw" --out "$OUT/ref$K" --radius "$R" --eye "$EYE" --target "$TARGET" \
      --fov $FOV --width $W --height $H >/dev/null
  "$M" --threads 2 render "$F" -o "$OUT/ours$K.exr" --background none --radius "$R" --eye "$EYE" \
      --target "$TARGET" --fov $FOV --width $W --height $H "$@" 2>/dev/null
  ARGS+=("$OUT/ref$K" "$OUT/ours$K.exr"); K=$((K + 1))
done
/usr/bin/python3 "$ROOT/scripts/temporal_score.py" "${ARGS[@]}"
