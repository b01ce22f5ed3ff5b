// libFuzzer target: VTK XML UnstructuredGrid (src/io/vtu.cpp): ascii, base64, appended; zlib, LZ4, LZMA.
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Vtu, "fuzz.vtu");
}
