// libFuzzer target: plain XYZ point clouds (src/io/text.cpp).
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Xyz, "fuzz.xyz");
}
