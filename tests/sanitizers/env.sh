# Sanitizer run-time options for the sanitizer build (scripts/test_sanitizers.sh)
# and the fuzzers (scripts/fuzz.sh). Source it: `source tests/sanitizers/env.sh`.
# Why each option is here: docs/sanitizers.md.
_meniscus_sanitizers="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1:strict_init_order=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=${_meniscus_sanitizers}/lsan.supp:print_suppressions=1"
unset _meniscus_sanitizers
