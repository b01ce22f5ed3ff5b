// libFuzzer target: the texture decoder of scene geometry (decodeTexture,
// src/io/image_decode.cpp: PNG through libpng, JPEG through libjpeg). What the
// library promises for any input (include/meniscus/geometry.h): an error
// names the image and says something, no exception escapes, and a texture is
// within the limits with 3 W H finite values in [0, 1].
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_reader.h"
#include "meniscus/geometry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace meniscus;
    static const std::string name = "fuzz.png";
    const Result<GeometryTexture> r = decodeTexture(ByteView(data, size), name);
    if (fuzz::checkError(r, name)) {
        const GeometryTexture& t = r.value();
        namespace lim = geometry_limits;
        if (t.width <= 0 || t.height <= 0 || t.width > lim::kMaxTextureSidePx || t.height > lim::kMaxTextureSidePx ||
            (long long)t.width * t.height > lim::kMaxTexturePixels)
            fuzz::broken("a texture outside the limits", name);
        if (t.rgb.size() != std::size_t(t.width) * std::size_t(t.height) * 3) fuzz::broken("a texture of the wrong size", name);
        for (float v : t.rgb)
            if (!(v >= 0.0f && v <= 1.0f)) fuzz::broken("a texel outside [0, 1]", name);
    }
    return 0;
}
