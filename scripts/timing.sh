# Sourced by scripts/test.sh, test_sanitizers.sh, fuzz.sh and .ci/run.
#
# timed LABEL COMMAND...   runs COMMAND, then prints "LABEL took M min" (also
#                          when it fails, whose exit status it returns).
# generator_args DIR       prints "-G Ninja" when ninja is installed and DIR has
#                          no build yet (ninja keeps both cores busy through the
#                          links; an existing build keeps its own generator).
timed() {
  local label=$1 t0=$SECONDS rc=0
  shift
  "$@" || rc=$?
  awk -v l="$label" -v s=$((SECONDS - t0)) -v rc=$rc \
    'BEGIN { printf "%s took %.1f min%s\n", l, s / 60, rc ? " (failed)" : "" }'
  return $rc
}

generator_args() {
  if command -v ninja >/dev/null && [ ! -f "$1/CMakeCache.txt" ]; then echo "-G Ninja"; fi
}
