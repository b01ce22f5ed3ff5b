// libFuzzer target: the environment map reader (src/io/environment_reader.cpp)
// for OpenEXR, which reads from a file, so the input is written to one first
// (fuzz_environment.h says what is checked).
#include "fuzz_environment.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::environmentMap(data, size, "fuzz_environment", ".exr");
}
