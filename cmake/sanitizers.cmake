# Sanitizer and fuzzing builds (docs/sanitizers.md). Included from the top-level
# CMakeLists.txt before any target, so the flags reach every target.
#
# MENISCUS_SANITIZE: AddressSanitizer (+ LeakSanitizer) and UndefinedBehaviorSanitizer
#   on everything (library, CLI, tests). Any UB report aborts (-fno-sanitize-recover),
#   so a test that trips one fails. scripts/test_sanitizers.sh builds it in build-asan.
# MENISCUS_FUZZ: the libFuzzer targets of fuzz/ (clang only). The library is compiled
#   with coverage instrumentation plus ASan/UBSan; the targets link libFuzzer's main.
option(MENISCUS_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(MENISCUS_FUZZ "Build the libFuzzer targets in fuzz/ (needs clang)" OFF)

# float-cast-overflow (NaN or out-of-range float -> int) is UB that GCC's
# -fsanitize=undefined leaves out; a renderer casts floats to pixel indices, so
# it is asked for by name. Float division by zero is not UB here (IEEE), so it
# stays off.
set(MENISCUS_SANITIZER_FLAGS -fsanitize=address,undefined,float-cast-overflow
                             -fno-sanitize-recover=all -fno-omit-frame-pointer)

if(MENISCUS_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "MENISCUS_FUZZ needs clang (libFuzzer), e.g. -DCMAKE_CXX_COMPILER=clang++; "
                        "this is ${CMAKE_CXX_COMPILER_ID}")
  endif()
  # -Wno-unknown-warning-option: the project's GCC-only -Wno-restrict.
  add_compile_options(-fsanitize=fuzzer-no-link -Wno-unknown-warning-option)
  message(STATUS "meniscus: fuzz targets (libFuzzer)")
endif()
# Both options together are one build: CI's sanitizer build (scripts/test_sanitizers.sh)
# compiles everything once with clang and builds the fuzz targets beside the tests,
# instead of compiling the library a third time for scripts/fuzz.sh.
if(MENISCUS_FUZZ OR MENISCUS_SANITIZE)
  add_compile_options(${MENISCUS_SANITIZER_FLAGS})
  add_link_options(-fsanitize=address,undefined)
endif()
if(MENISCUS_SANITIZE)
  # Libraries stay loaded until exit, so LeakSanitizer can name what Mesa, GLFW and
  # X11 leak (the why is in the file); linked into every executable: the
  # top-level CMakeLists.txt calls link_libraries() with it after the module
  # libraries are defined, so the installed package never references it.
  add_library(meniscus_keep_libraries_loaded OBJECT
              ${PROJECT_SOURCE_DIR}/tests/sanitizers/keep_libraries_loaded.cpp)
  add_link_options(-Wl,--export-dynamic-symbol=dlclose)
  message(STATUS "meniscus: sanitizer build (ASan, LSan, UBSan)")
endif()
