#!/usr/bin/env bash
# Builds the reader fuzz targets (fuzz/) with clang, libFuzzer, ASan and UBSan in
# build-fuzz (or in FUZZ_BUILD_DIR, a tree already configured with
# -DMENISCUS_FUZZ=ON: .ci/run passes build-asan, where scripts/test_sanitizers.sh
# built them beside the tests), then runs each for a bounded time: first over its seed corpus and
# regression inputs (fuzz/corpus/<reader>, fuzz/regressions/<reader>), then on
# inputs libFuzzer derives from them. Fails if any target crashes, trips a
# sanitizer, breaks a reader's promise (fuzz/fuzz_reader.h), runs out of its
# memory limit or hangs; the input that did it is left in
# <build>/artifacts/<reader>/. .ci/run calls this; docs/sanitizers.md says
# how to fuzz longer.
#
#   scripts/fuzz.sh [READER...]     (default: every reader in fuzz/CMakeLists.txt)
#   FUZZ_SECONDS=600 scripts/fuzz.sh ply    one reader, ten minutes
#
# Time: a named reader runs 25 s. The default run shares one budget,
# FUZZ_BUDGET target-seconds (325: the 13 targets x 25 s the phase had before
# the geometry readers joined), evenly among its targets, so a new target
# takes its slice from the others and the phase stays as long as it was.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
clangxx=${FUZZ_CXX:-clang++}
if ! command -v "$clangxx" >/dev/null; then
  echo "fuzz: $clangxx not found; the fuzzers need clang and libFuzzer (Debian: apt-get install clang libclang-rt-14-dev)" >&2
  exit 1
fi
readers=("$@")
seconds=${FUZZ_SECONDS:-25}
if [ ${#readers[@]} -eq 0 ]; then
  read -r -a readers <<<"$(sed -n 's/^set(MENISCUS_FUZZ_READERS \(.*\))$/\1/p' fuzz/CMakeLists.txt)"
  if [ -z "${FUZZ_SECONDS:-}" ]; then
    seconds=$(( ${FUZZ_BUDGET:-325} / ${#readers[@]} ))
    [ "$seconds" -ge 5 ] || seconds=5
  fi
fi

# Only the reader code is needed: no GL, tests or bench.
source scripts/timing.sh
dir=${FUZZ_BUILD_DIR:-build-fuzz}
if ! grep -q '^MENISCUS_FUZZ:BOOL=ON' "$dir/CMakeCache.txt" 2>/dev/null; then
  if [ -n "${FUZZ_BUILD_DIR:-}" ]; then
    echo "fuzz: $dir is not a fuzz build (-DMENISCUS_FUZZ=ON)" >&2
    exit 1
  fi
  # shellcheck disable=SC2046  # the generator is one or two words, or none
  cmake -S . -B "$dir" $(generator_args "$dir") -DCMAKE_CXX_COMPILER="$clangxx" -DCMAKE_BUILD_TYPE=Debug \
        -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" -DMENISCUS_FUZZ=ON -DMENISCUS_GL=OFF \
        -DMENISCUS_BUILD_TESTS=OFF -DMENISCUS_BUILD_BENCH=OFF >/dev/null
fi
targets=()
for r in "${readers[@]}"; do targets+=("fuzz_$r"); done
timed "fuzz.sh: the build" cmake --build "$dir" -j"$jobs" --target "${targets[@]}"

source tests/sanitizers/env.sh
# One reader: the inputs libFuzzer adds go to $dir/corpus/<reader> (the
# first folder), never into the repository's seeds. Limits: one input may run
# 10 s, the process may use 2 GiB, and no single allocation may exceed 256 MiB,
# a bound no honest reader needs for inputs of a few KB (a count from a header
# trusted before its bytes exist shows up here).
fuzz_one() {
  local r=$1 regress=fuzz/regressions/$1
  mkdir -p "$dir/corpus/$r" "$dir/artifacts/$r"
  [ -d "$regress" ] || regress=""
  if "$dir/fuzz/fuzz_$r" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -malloc_limit_mb=256 -print_final_stats=1 -artifact_prefix="$dir/artifacts/$r/" \
       "$dir/corpus/$r" "fuzz/corpus/$r" $regress >"$dir/fuzz_$r.log" 2>&1; then
    echo "fuzz: $r: $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$dir/fuzz_$r.log" | grep -o '[0-9]*$') runs in ${seconds} s, no failure"
  else
    echo "fuzz: $r FAILED; log $dir/fuzz_$r.log, input in $dir/artifacts/$r/:" >&2
    tail -n 60 "$dir/fuzz_$r.log" >&2
    return 1
  fi
}
export -f fuzz_one
export seconds dir
timed "fuzz.sh: the runs" bash -c 'printf "%s\n" "$@" | xargs -P "$0" -I{} bash -c "fuzz_one {}"' "$jobs" "${readers[@]}"
