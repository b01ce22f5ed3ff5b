// Backdrops (include/meniscus/backdrop.h): a picture's colour and depth from
// OpenEXR files (OpenEXR's InputFile, every pixel type read as float; its
// exceptions caught), or its colour from a PNG or JPEG (decodeTexture, sRGB to
// linear). Bounded as every reader is: the file's size and the picture's
// pixel count are checked, and the memory budget asked, before anything is
// allocated.
#include "meniscus/backdrop.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include "meniscus/geometry.h"
#include "meniscus/io.h"
#include "meniscus/memory_budget.h"

namespace meniscus {

namespace {

std::string lowerExtension(const std::filesystem::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// The channel of `header` standing for `wanted` ("R", "Z"): one of that very
// name; else the one whose last part (after the last '.') is `wanted`, a name
// in layer `layer` ("Combined", "Depth") winning over the others; none when
// there is no such channel, an error when several remain.
Result<std::optional<std::string>> findChannel(const Imf::Header& header, const std::string& wanted,
                                               const std::string& layer, const std::string& file) {
    if (header.channels().findChannel(wanted.c_str())) return std::optional<std::string>(wanted);
    std::vector<std::string> all, inLayer;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
        const std::string name = it.name();
        const std::size_t dot = name.rfind('.');
        if (dot == std::string::npos || name.substr(dot + 1) != wanted) continue;
        all.push_back(name);
        const std::string head = name.substr(0, dot);
        if (head == layer || (head.size() > layer.size() && head.ends_with("." + layer))) inLayer.push_back(name);
    }
    const std::vector<std::string>& pick = inLayer.empty() ? all : inLayer;
    if (pick.empty()) return std::optional<std::string>();
    if (pick.size() > 1) {
        std::string names;
        for (const std::string& n : pick) names += (names.empty() ? "" : ", ") + n;
        return makeError(file, "backdrop: several channels could be " + wanted + " (" + names + ")");
    }
    return std::optional<std::string>(pick[0]);
}

// Every channel's name, for messages.
std::string channelList(const Imf::Header& header) {
    std::string names;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
        names += (names.empty() ? "" : ", ") + std::string(it.name());
    return names.empty() ? "none" : names;
}

Status checkFileSize(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return makeError(name, "backdrop: no such file");
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (ec) return makeError(name, "backdrop: cannot read its size");
    if (bytes > kMaxBackdropFileBytes)
        return makeError(name, "backdrop: " + std::to_string(bytes) + " bytes, more than the limit of " +
                                   std::to_string(kMaxBackdropFileBytes));
    return okStatus();
}

Status checkSize(long long w, long long h, const std::string& name) {
    if (w <= 0 || h <= 0) return makeError(name, "backdrop: an empty picture");
    if (w > kMaxBackdropSidePx || h > kMaxBackdropSidePx || w * h > kMaxBackdropPixels)
        return makeError(name, "backdrop: " + std::to_string(w) + "x" + std::to_string(h) +
                                   " pixels, more than the limit of " + std::to_string(kMaxBackdropSidePx) +
                                   " a side and " + std::to_string(kMaxBackdropPixels) + " in all");
    // Colour (4 floats) and depth, and the renderer's converted copy of both.
    const std::uint64_t need = std::uint64_t(w) * std::uint64_t(h) * 2 * (sizeof(glm::vec4) + sizeof(float));
    if (Status st = checkMemory(need, "the backdrop " + name, "render a smaller picture"); !st)
        return makeError(name, st.error().message);
    return okStatus();
}

// One EXR file: its size, and the channels asked for (each a name found by
// findChannel, or empty: not read) into `out` (channels floats a pixel).
struct ExrPicture {
    int width = 0, height = 0;
    std::vector<float> values;  // width x height x channels
};

Result<ExrPicture> readExrChannels(const std::string& name, const std::vector<std::string>& channels) {
    Imf::InputFile file(name.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i dw = header.dataWindow(), disp = header.displayWindow();
    if (dw != disp)
        return makeError(name, "backdrop: its data window is not its display window (a cropped or overscanned "
                               "render); save the whole frame");
    const long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
    if (Status st = checkSize(w, h, name); !st) return st.error();
    ExrPicture out;
    out.width = int(w);
    out.height = int(h);
    const std::size_t n = channels.size();
    out.values.assign(std::size_t(w) * std::size_t(h) * n, 0.0f);
    char* base = reinterpret_cast<char*>(out.values.data()) -
                 (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * std::ptrdiff_t(w)) *
                     std::ptrdiff_t(n * sizeof(float));
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < n; ++c)
        fb.insert(channels[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), n * sizeof(float),
                                          std::size_t(w) * n * sizeof(float)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return out;
}

// The colour (and, with `withDepth`, the depth) of an EXR file.
Status readExrBackdrop(const std::string& name, bool withDepth, BackdropImage& out) {
    Imf::InputFile probe(name.c_str());
    const Imf::Header& header = probe.header();
    std::vector<std::string> names;
    for (const char* c : {"R", "G", "B"}) {
        auto ch = findChannel(header, c, "Combined", name);
        if (!ch) return ch.error();
        if (!*ch)
            return makeError(name, std::string("backdrop: no ") + c + " channel (its channels: " +
                                       channelList(header) + ")");
        names.push_back(**ch);
    }
    auto alpha = findChannel(header, "A", "Combined", name);
    if (!alpha) return alpha.error();
    if (*alpha) names.push_back(**alpha);
    const bool hasAlpha = bool(*alpha);
    if (withDepth) {
        auto z = findChannel(header, "Z", "Depth", name);
        if (!z) return z.error();
        if (!*z)
            return makeError(name, "backdrop: no depth channel Z (its channels: " + channelList(header) +
                                       "); give the depth as its own file (--backdrop-depth)");
        names.push_back(**z);
    }
    auto picture = readExrChannels(name, names);
    if (!picture) return picture.error();
    const std::size_t n = names.size(), count = std::size_t(picture->width) * std::size_t(picture->height);
    out.width = picture->width;
    out.height = picture->height;
    out.color.resize(count);
    if (withDepth) out.depth.resize(count);
    const std::vector<float>& v = picture->values;
    for (std::size_t i = 0; i < count; ++i) {
        const float* p = &v[i * n];
        glm::vec4 c(p[0], p[1], p[2], hasAlpha ? p[3] : 1.0f);
        for (int k = 0; k < 4; ++k) c[k] = std::isfinite(c[k]) ? c[k] : 0.0f;
        out.color[i] = c;
        if (withDepth) out.depth[i] = p[n - 1];
    }
    return okStatus();
}

// The depth of a separate EXR file: its Z channel, or its only channel.
Result<ExrPicture> readExrDepth(const std::string& name) {
    Imf::InputFile probe(name.c_str());
    const Imf::Header& header = probe.header();
    auto z = findChannel(header, "Z", "Depth", name);
    if (!z) return z.error();
    std::string channel;
    if (*z) {
        channel = **z;
    } else {
        int count = 0;
        for (auto it = header.channels().begin(); it != header.channels().end(); ++it, ++count) channel = it.name();
        if (count != 1)
            return makeError(name, "backdrop depth: no Z channel and not a single channel (its channels: " +
                                       channelList(header) + ")");
    }
    return readExrChannels(name, {channel});
}

}  // namespace

Result<BackdropDepth> parseBackdropDepth(std::string_view text) {
    const auto bad = [&] {
        return makeError("", "backdrop depth kind '" + std::string(text) +
                                 "': one of linear, ray, blender, window:NEAR,FAR (metres, 0 < NEAR < FAR)");
    };
    BackdropDepth d;
    if (text == "linear") d.kind = BackdropDepthKind::Linear;
    else if (text == "ray") d.kind = BackdropDepthKind::Ray;
    else if (text == "blender") d.kind = BackdropDepthKind::Blender;
    else if (text.starts_with("window:")) {
        const std::string_view planes = text.substr(7);
        const std::size_t comma = planes.find(',');
        if (comma == std::string_view::npos) return bad();
        const std::string nearText(planes.substr(0, comma)), farText(planes.substr(comma + 1));
        try {
            std::size_t a = 0, b = 0;
            d.nearM = std::stof(nearText, &a);
            d.farM = std::stof(farText, &b);
            if (a != nearText.size() || b != farText.size()) return bad();
        } catch (const std::exception&) {
            return bad();
        }
        if (!(d.nearM > 0.0f) || !(d.farM > d.nearM) || !std::isfinite(d.farM)) return bad();
        d.kind = BackdropDepthKind::Window;
    } else {
        return bad();
    }
    return d;
}

std::string backdropDepthText(const BackdropDepth& d) {
    switch (d.kind) {
        case BackdropDepthKind::Linear: return "linear";
        case BackdropDepthKind::Ray: return "ray";
        case BackdropDepthKind::Blender: return "blender";
        case BackdropDepthKind::Window: break;
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, "window:%g,%g", double(d.nearM), double(d.farM));
    return buf;
}

Result<BackdropImage> readBackdrop(const std::filesystem::path& color, const std::filesystem::path& depth,
                                   const BackdropDepth& convention) {
    const std::string name = color.string();
    try {
        if (Status st = checkFileSize(color); !st) return st.error();
        if (!depth.empty())
            if (Status st = checkFileSize(depth); !st) return st.error();
        BackdropImage out;
        out.name = name;
        out.convention = convention;
        const std::string ext = lowerExtension(color);
        if (ext == ".exr") {
            if (Status st = readExrBackdrop(name, depth.empty(), out); !st) return st.error();
        } else if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") {
            if (depth.empty())
                return makeError(name, "backdrop: a PNG or JPEG holds no depth; give it as its own file "
                                       "(--backdrop-depth) or use an OpenEXR file with a Z channel");
            auto bytes = readFileBytes(color);
            if (!bytes) return bytes.error();
            auto image = decodeTexture(ByteView(*bytes), name);
            if (!image) return image.error();
            if (Status st = checkSize(image->width, image->height, name); !st) return st.error();
            out.width = image->width;
            out.height = image->height;
            out.color.resize(std::size_t(out.width) * std::size_t(out.height));
            for (std::size_t i = 0; i < out.color.size(); ++i)
                out.color[i] = glm::vec4(image->rgb[3 * i], image->rgb[3 * i + 1], image->rgb[3 * i + 2], 1.0f);
        } else {
            return makeError(name, "backdrop: not an OpenEXR (.exr), PNG or JPEG file");
        }
        if (!depth.empty()) {
            const std::string depthName = depth.string();
            if (lowerExtension(depth) != ".exr") return makeError(depthName, "backdrop depth: not an OpenEXR file");
            auto d = readExrDepth(depthName);
            if (!d) return d.error();
            if (d->width != out.width || d->height != out.height)
                return makeError(depthName, "backdrop depth: " + std::to_string(d->width) + "x" +
                                                std::to_string(d->height) + " pixels, the colour " + name + " " +
                                                std::to_string(out.width) + "x" + std::to_string(out.height));
            out.depth = std::move(d->values);
        }
        return out;
    } catch (const std::bad_alloc&) {
        return makeError(name, "backdrop: out of memory");
    } catch (const std::exception& e) {
        return makeError(name, std::string("backdrop: not a readable picture: ") + e.what());
    } catch (...) {
        return makeError(name, "backdrop: not a readable picture");
    }
}

Result<BackdropImage> makeBackdrop(int width, int height, std::span<const float> color, int channels,
                                   std::span<const float> depth, const BackdropDepth& convention) {
    const std::string name = "the backdrop's arrays";
    if (Status st = checkSize(width, height, name); !st) return st.error();
    if (channels != 3 && channels != 4) return makeError(name, "the colour has 3 (RGB) or 4 (RGBA) channels");
    const std::size_t count = std::size_t(width) * std::size_t(height);
    if (color.size() != count * std::size_t(channels))
        return makeError(name, "the colour has " + std::to_string(color.size()) + " values, not " +
                                   std::to_string(width) + "x" + std::to_string(height) + "x" +
                                   std::to_string(channels));
    if (depth.size() != count)
        return makeError(name, "the depth has " + std::to_string(depth.size()) + " values, not " +
                                   std::to_string(width) + "x" + std::to_string(height));
    try {
        BackdropImage out;
        out.name = name;
        out.width = width;
        out.height = height;
        out.convention = convention;
        out.color.resize(count);
        for (std::size_t i = 0; i < count; ++i) {
            const float* p = &color[i * std::size_t(channels)];
            glm::vec4 c(p[0], p[1], p[2], channels == 4 ? p[3] : 1.0f);
            for (int k = 0; k < 4; ++k) c[k] = std::isfinite(c[k]) ? c[k] : 0.0f;
            out.color[i] = c;
        }
        out.depth.assign(depth.begin(), depth.end());
        return out;
    } catch (const std::bad_alloc&) {
        return makeError(name, "out of memory");
    }
}

}  // namespace meniscus
