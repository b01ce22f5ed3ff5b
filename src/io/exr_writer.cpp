// writeExr / writeExrAovs: OpenEXR scanline files of named float channels.
//
// - Every channel is FLOAT (32-bit), so values (depth +inf included) are kept
//   bit for bit; nothing is clamped or converted.
// - ZIP compression, INCREASING_Y line order, data window 0..W-1 x 0..H-1.
// - Row order: Image row 0 is the top row and is written as scanline y = 0,
//   the EXR's first scanline, which viewers show at the top (no flip).
// - OpenEXR sorts channels by name in the header; that is fine for readers.
// - Written through writeAtomically: a failed write leaves no file behind.
//   OpenEXR exceptions are caught and turned into an Error naming the file.
#include <exception>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>

#include "atomic_file.h"
#include "meniscus/io.h"

namespace meniscus {

Status writeExr(const std::filesystem::path& path, const std::vector<ExrChannel>& channels) {
    const std::string name = path.string();
    if (channels.empty()) return makeError(name, "no channels to write");

    std::set<std::string> names;
    const Image<float>* first = channels.front().image;
    for (const ExrChannel& c : channels) {
        if (c.name.empty()) return makeError(name, "EXR channel with an empty name");
        if (!names.insert(c.name).second) return makeError(name, "duplicate EXR channel '" + c.name + "'");
        if (!c.image) return makeError(name, "EXR channel '" + c.name + "' has no image");
        const Image<float>& im = *c.image;
        if (im.width <= 0 || im.height <= 0 || im.empty())
            return makeError(name, "EXR channel '" + c.name + "' is an empty image");
        if (im.pixels.size() != std::size_t(im.width) * std::size_t(im.height))
            return makeError(name, "EXR channel '" + c.name + "' has a pixel count that does not match its size");
        if (first && (im.width != first->width || im.height != first->height))
            return makeError(name, "EXR channel '" + c.name + "' is " + std::to_string(im.width) + "x" +
                                       std::to_string(im.height) + " but '" + channels.front().name + "' is " +
                                       std::to_string(first->width) + "x" + std::to_string(first->height));
    }
    const int width = first->width;
    const int height = first->height;

    return writeAtomically(path, [&](const std::filesystem::path& tmp) -> Status {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return makeError(name, "cannot open for writing");
        try {
            Imf::Header header(width, height);  // data window (0,0)-(W-1,H-1)
            header.compression() = Imf::ZIP_COMPRESSION;
            header.lineOrder() = Imf::INCREASING_Y;
            Imf::FrameBuffer frameBuffer;
            for (const ExrChannel& c : channels) {
                header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
                // Slice wants a non-const pointer; OutputFile only reads from it.
                char* base = reinterpret_cast<char*>(const_cast<float*>(c.image->pixels.data()));
                frameBuffer.insert(c.name, Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                                      sizeof(float) * std::size_t(width)));
            }
            Imf::StdOFStream stream(out, name.c_str());
            {
                // The line offset table is written when the OutputFile is destroyed.
                Imf::OutputFile file(stream, header);
                file.setFrameBuffer(frameBuffer);
                file.writePixels(height);
            }
        } catch (const std::exception& e) {
            return makeError(name, std::string("EXR write failed: ") + e.what());
        } catch (...) {
            return makeError(name, "EXR write failed");
        }
        out.close();
        if (!out) return makeError(name, "write failed (disk full?)");
        return okStatus();
    });
}

Status writeExrAovs(const std::filesystem::path& path, const Aovs& aovs) {
    // Split vector images into one float plane per component.
    // Size fields are copied as they are, so writeExr still sees a bad size.
    auto plane = [](const auto& image, auto component) {
        Image<float> out;
        out.width = image.width;
        out.height = image.height;
        out.pixels.reserve(image.pixels.size());
        for (const auto& p : image.pixels) out.pixels.push_back(component(p));
        return out;
    };

    std::vector<Image<float>> planes;
    planes.reserve(8);  // stable addresses for the ExrChannel pointers below
    std::vector<ExrChannel> channels;
    auto add = [&](const char* channelName, Image<float> image) {
        planes.push_back(std::move(image));
        channels.push_back({channelName, &planes.back()});
    };

    if (!aovs.color.empty()) {
        add("R", plane(aovs.color, [](const glm::vec4& p) { return p.r; }));
        add("G", plane(aovs.color, [](const glm::vec4& p) { return p.g; }));
        add("B", plane(aovs.color, [](const glm::vec4& p) { return p.b; }));
        add("A", plane(aovs.color, [](const glm::vec4& p) { return p.a; }));
    }
    // coverage: 1 where fluid was splatted, 0 elsewhere. A is the colour's
    // alpha, which over the studio background is 1 everywhere.
    const Image<float>& covered = aovs.rawDepth.empty() ? aovs.depth : aovs.rawDepth;
    if (!covered.empty()) add("coverage", plane(covered, [](float z) { return z < std::numeric_limits<float>::infinity() ? 1.0f : 0.0f; }));
    if (!aovs.depth.empty()) channels.push_back({"Z", &aovs.depth});
    if (!aovs.rawDepth.empty()) channels.push_back({"Zraw", &aovs.rawDepth});
    if (!aovs.normal.empty()) {
        add("N.X", plane(aovs.normal, [](const glm::vec3& n) { return n.x; }));
        add("N.Y", plane(aovs.normal, [](const glm::vec3& n) { return n.y; }));
        add("N.Z", plane(aovs.normal, [](const glm::vec3& n) { return n.z; }));
    }
    if (!aovs.thickness.empty()) channels.push_back({"T", &aovs.thickness});
    if (!aovs.noise.empty()) channels.push_back({"Noise", &aovs.noise});
    if (!aovs.foam.empty()) channels.push_back({"foam", &aovs.foam});
    if (!aovs.whitening.empty()) channels.push_back({"whitening", &aovs.whitening});
    if (!aovs.spray.empty()) channels.push_back({"spray", &aovs.spray});
    if (!aovs.silhouette.empty()) channels.push_back({"silhouette", &aovs.silhouette});
    if (!aovs.fluid.empty()) channels.push_back({"fluid", &aovs.fluid});

    if (channels.empty()) return makeError(path.string(), "no image to write: every AOV is empty");
    return writeExr(path, channels);
}

}  // namespace meniscus
