// The environment map's reader (docs/pipeline.md#environment-map): an
// equirectangular OpenEXR image into linear RGB floats, bounded (the file's
// size and the image's pixel count are checked before anything is allocated)
// and with OpenEXR's exceptions caught, so a bad file is an Error naming it.
// Radiance .hdr pictures are decoded by radiance_hdr.cpp, bounded the same.
#include "meniscus/environment.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <new>
#include <string>
#include <system_error>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include "radiance_hdr.h"

namespace meniscus {

Result<EnvironmentImage> readEnvironmentMap(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return makeError(name, "environment map: no such file");
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (ec) return makeError(name, "environment map: cannot read its size");
    if (bytes > kMaxEnvironmentFileBytes)
        return makeError(name, "environment map: " + std::to_string(bytes) + " bytes, more than the limit of " +
                                   std::to_string(kMaxEnvironmentFileBytes));
    if (ext == ".hdr" || ext == ".pic") {
        // The whole file (at most the limit above), then decoded in memory.
        std::vector<std::uint8_t> data;
        try {
            data.resize(std::size_t(bytes));
            std::ifstream in(path, std::ios::binary);
            if (!in.read(reinterpret_cast<char*>(data.data()), std::streamsize(data.size())))
                return makeError(name, "environment map: cannot read the file");
        } catch (const std::exception&) {
            return makeError(name, "environment map: cannot read the file (out of memory)");
        }
        try {
            return io::decodeRadianceHdr(data.data(), data.size(), name);
        } catch (const std::bad_alloc&) {
            return makeError(name, "environment map: out of memory");
        }
    }
    try {
        Imf::InputFile file(name.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i dw = header.dataWindow();
        const long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
        if (w <= 0 || h <= 0) return makeError(name, "environment map: an empty image");
        if (w > kMaxEnvironmentWidth || h > kMaxEnvironmentHeight)
            return makeError(name, "environment map: " + std::to_string(w) + "x" + std::to_string(h) +
                                       " pixels, more than the limit of " + std::to_string(kMaxEnvironmentWidth) +
                                       "x" + std::to_string(kMaxEnvironmentHeight));
        for (const char* c : {"R", "G", "B"})
            if (!header.channels().findChannel(c))
                return makeError(name, std::string("environment map: no ") + c +
                                           " channel (an RGB image is expected)");
        EnvironmentImage image;
        image.width = int(w);
        image.height = int(h);
        image.rgb.assign(std::size_t(w) * std::size_t(h) * 3, 0.0f);
        // The slices' base is where pixel (0, 0) would be: the data window may
        // start elsewhere (OpenEXR addresses base + x xStride + y yStride).
        char* base = reinterpret_cast<char*>(image.rgb.data()) -
                     (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * std::ptrdiff_t(w)) *
                         std::ptrdiff_t(3 * sizeof(float));
        Imf::FrameBuffer fb;
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 3 * sizeof(float),
                                           std::size_t(w) * 3 * sizeof(float)));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        // Radiance is finite and non-negative; anything else would spread NaN
        // or negative light through the bilinear filter.
        for (float& v : image.rgb) v = std::isfinite(v) && v > 0.0f ? v : 0.0f;
        return image;
    } catch (const std::exception& e) {
        return makeError(name, std::string("environment map: not a readable OpenEXR file: ") + e.what());
    } catch (...) {
        return makeError(name, "environment map: not a readable OpenEXR file");
    }
}

}  // namespace meniscus
