// Shared body of the environment map fuzz targets (fuzz_environment.cpp,
// OpenEXR; fuzz_environment_hdr.cpp, Radiance .hdr): the input written to a
// file of the given extension (both decoders read files) and read through
// readEnvironmentMap. What the library promises for any input
// (include/meniscus/environment.h): an error names the file and says
// something, no exception escapes, and a map is within the bounds with 3 W H
// finite, non-negative values.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "fuzz_reader.h"
#include "meniscus/environment.h"

namespace meniscus::fuzz {

inline int environmentMap(const std::uint8_t* data, std::size_t size, const char* stem, const char* extension) {
    static const std::string name = (std::filesystem::temp_directory_path() /
                                     (std::string(stem) + "_" + std::to_string(getpid()) + extension))
                                        .string();
    {
        std::ofstream out(name, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    const Result<EnvironmentImage> r = readEnvironmentMap(name);
    if (checkError(r, name)) {
        const EnvironmentImage& m = r.value();
        if (m.width <= 0 || m.height <= 0 || m.width > kMaxEnvironmentWidth || m.height > kMaxEnvironmentHeight)
            broken("a map outside the bounds", name);
        if (m.rgb.size() != std::size_t(m.width) * std::size_t(m.height) * 3) broken("a map of the wrong size", name);
        for (float v : m.rgb)
            if (!std::isfinite(v) || v < 0.0f) broken("a non-finite or negative texel", name);
    }
    std::remove(name.c_str());
    return 0;
}

}  // namespace meniscus::fuzz
