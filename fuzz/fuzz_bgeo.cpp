// libFuzzer target: classic BGEO (src/io/bgeo.cpp), plain or gzip-compressed.
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Bgeo, "fuzz.bgeo");
}
