// libFuzzer target: the PLY mesh reader (src/io/mesh_reader.cpp), ascii and
// binary of both byte orders.
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    meniscus::fuzz::checkMesh(meniscus::parsePlyMesh(meniscus::ByteView(data, size), "fuzz.ply"), "fuzz.ply");
    return 0;
}
