// libFuzzer target: CSV with a header row (src/io/text.cpp).
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Csv, "fuzz.csv");
}
