#!/usr/bin/env bash
# Builds everything with AddressSanitizer (+ LeakSanitizer) and
# UndefinedBehaviorSanitizer in build-asan (-O1 -g, no bench tool) and runs the
# whole ctest suite there, GL tests included (Mesa llvmpipe), without MPI
# (OpenMPI's own allocations would flood LeakSanitizer; the mpirun tests run in
# the Release build, and this build tests what a build without MPI says under
# mpirun, cli_test's ANonMpiBuildUnderMpirunSaysSo). Any sanitizer
# report fails its test. .ci/run calls this after scripts/test.sh; see
# docs/sanitizers.md for the options and the suppressions.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
# The environment the sanitizers read (the tests' own child processes, such as
# the CLI, inherit it): tests/sanitizers/env.sh.
source tests/sanitizers/env.sh
source scripts/timing.sh
# shellcheck disable=SC2046  # the generator is one or two words, or none
cmake -S . -B build-asan $(generator_args build-asan) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
      -DMENISCUS_SANITIZE=ON -DMENISCUS_BUILD_BENCH=OFF -DMENISCUS_MPI=OFF >/dev/null
timed "test_sanitizers.sh: the build" cmake --build build-asan -j"$jobs"
timed "test_sanitizers.sh: the tests" ctest --test-dir build-asan --output-on-failure -j"$jobs"
