// libFuzzer target: mesh files through Assimp, from memory (parseGeometryMesh,
// src/io/geometry.cpp: the same import and checks as readGeometryMesh). The
// input's first byte picks the format (its extension), the rest is the file.
#include <iterator>

#include "fuzz_geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const char* const kNames[] = {"fuzz.obj", "fuzz.ply", "fuzz.stl", "fuzz.gltf", "fuzz.off"};
    if (size == 0) return 0;
    const std::string name = kNames[data[0] % std::size(kNames)];
    const auto o = meniscus::parseGeometryMesh(meniscus::ByteView(data + 1, size - 1), name);
    if (meniscus::fuzz::checkError(o, name)) meniscus::fuzz::checkObject(o.value());
    return 0;
}
