// libFuzzer target: the OBJ mesh reader (src/io/mesh_reader.cpp).
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    meniscus::fuzz::checkMesh(meniscus::parseObjMesh(meniscus::ByteView(data, size), "fuzz.obj"), "fuzz.obj");
    return 0;
}
