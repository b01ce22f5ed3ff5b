// libFuzzer target: the Radiance .hdr environment map decoder
// (src/io/radiance_hdr.cpp), through readEnvironmentMap as a .hdr file
// (fuzz_environment.h says what is checked).
#include "fuzz_environment.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::environmentMap(data, size, "fuzz_environment_hdr", ".hdr");
}
