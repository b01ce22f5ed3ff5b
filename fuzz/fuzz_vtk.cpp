// libFuzzer target: legacy VTK (src/io/vtk_legacy.cpp), ascii and binary.
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::VtkLegacy, "fuzz.vtk");
}
