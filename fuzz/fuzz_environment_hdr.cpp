// libFuzzer target: the Radiance .hdr environment map decoder
// (src/io/radiance_hdr.cpp), through readEnvironmentMap as a .hdr file. What
// the library promises for any input (include/meniscus/environment.h): an
// error names the file and says something, no exception escapes, and a map is
// within the bounds with 3 W H finite, non-negative values.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "fuzz_reader.h"
#include "meniscus/environment.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace meniscus;
    static const std::string name =
        (std::filesystem::temp_directory_path() / ("fuzz_environment_hdr_" + std::to_string(getpid()) + ".hdr")).string();
    {
        std::ofstream out(name, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    const Result<EnvironmentImage> r = readEnvironmentMap(name);
    if (fuzz::checkError(r, name)) {
        const EnvironmentImage& m = r.value();
        if (m.width <= 0 || m.height <= 0 || m.width > kMaxEnvironmentWidth || m.height > kMaxEnvironmentHeight)
            fuzz::broken("a map outside the bounds", name);
        if (m.rgb.size() != std::size_t(m.width) * std::size_t(m.height) * 3) fuzz::broken("a map of the wrong size", name);
        for (float v : m.rgb)
            if (!std::isfinite(v) || v < 0.0f) fuzz::broken("a non-finite or negative texel", name);
    }
    std::remove(name.c_str());
    return 0;
}
