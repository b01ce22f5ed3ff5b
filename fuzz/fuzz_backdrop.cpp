// libFuzzer target: the backdrop reader (src/io/backdrop_reader.cpp) on
// OpenEXR files, which it reads from disk, so the input is written to one
// first. What the library promises for any input (include/meniscus/backdrop.h):
// an error names the file and says something, no exception escapes, and a
// backdrop is within the bounds with W H finite colours and W H depths.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "fuzz_reader.h"
#include "meniscus/backdrop.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace meniscus;
    static const std::string name =
        (std::filesystem::temp_directory_path() / ("fuzz_backdrop_" + std::to_string(getpid()) + ".exr")).string();
    {
        std::ofstream out(name, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    const Result<BackdropImage> r = readBackdrop(name, {}, {});
    if (fuzz::checkError(r, name)) {
        const BackdropImage& b = r.value();
        if (b.width <= 0 || b.height <= 0 || b.width > kMaxBackdropSidePx || b.height > kMaxBackdropSidePx)
            fuzz::broken("a backdrop outside the bounds", name);
        const std::size_t n = std::size_t(b.width) * std::size_t(b.height);
        if (b.color.size() != n || b.depth.size() != n) fuzz::broken("a backdrop of the wrong size", name);
        for (const auto& c : b.color)
            if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b) || !std::isfinite(c.a))
                fuzz::broken("a non-finite colour", name);
    }
    std::remove(name.c_str());
    return 0;
}
