// libFuzzer target: VTK XML PolyData (src/io/vtu.cpp, the .vtp side of the XML reader).
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Vtu, "fuzz.vtp");
}
