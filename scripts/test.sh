#!/usr/bin/env bash
# Configures, builds (Release) and runs every test with ctest. The README's test
# command and .ci/run both call this script.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
source scripts/timing.sh
# shellcheck disable=SC2046  # the generator is one or two words, or none
cmake -S . -B build $(generator_args build) -DCMAKE_BUILD_TYPE=Release >/dev/null
timed "test.sh: the build" cmake --build build -j"$jobs"
timed "test.sh: the tests" ctest --test-dir build --output-on-failure -j"$jobs"
