// libFuzzer target: PLY (src/io/ply.cpp), ascii and binary of both byte orders.
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Ply, "fuzz.ply");
}
