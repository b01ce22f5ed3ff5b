// libFuzzer target: SPlisHSPlasH scene files as scene geometry
// (parseSplishSplashScene, src/io/geometry.cpp): JSON text in, the rigid
// bodies and boundaries as checked objects out (fuzz_geometry.h). Their
// geometry files resolve under a folder that does not exist, so the run reads
// no files.
#include <string_view>

#include "fuzz_geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string name = "fuzz.json";
    const auto g = meniscus::parseSplishSplashScene(std::string_view(reinterpret_cast<const char*>(data), size), name,
                                                    "/nonexistent-fuzz-splishsplash-dir");
    if (!meniscus::fuzz::checkAnyError(g)) return 0;
    for (const meniscus::GeometryObject& o : g->objects) meniscus::fuzz::checkObject(o);
    return 0;
}
