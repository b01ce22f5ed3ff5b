// Files: read(), sequence(), demo(), estimate_radius(), write_png().
#include <filesystem>
#include <string>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "module.h"

namespace meniscus::py {

namespace fs = std::filesystem;

namespace {

// An Error of reading `path` as OSError; FileNotFoundError when it is not there.
[[noreturn]] void throwRead(const Error& e, const fs::path& path) {
    std::error_code ec;
    throwOs(e.describe(), fs::exists(path, ec) ? PyExc_OSError : PyExc_FileNotFoundError);
}

pb::dict read(const fs::path& path, bool allowEmpty) {
    Result<ParticleSet> set = makeError("", "");
    {
        pb::gil_scoped_release unlocked;
        set = readParticles(path, ParticleFormat::Auto, allowEmpty);
    }
    if (!set) throwRead(set.error(), path);
    warnAll(set->warnings);
    return particleDict(std::move(*set));
}

std::vector<std::string> sequence(const std::string& spec) {
    auto frames = expandSequence(spec);
    if (!frames) throwOs(frames.error().describe(), PyExc_FileNotFoundError);
    std::vector<std::string> out;
    for (const fs::path& f : *frames) out.push_back(f.string());
    return out;
}

pb::dict demo() {
    auto set = parseParticles(demoFrameBytes(), kDemoFrameName);
    if (!set) throwRuntime(set.error().describe());  // embedded in the build: cannot fail
    return particleDict(std::move(*set));
}

float estimateRadiusOf(pb::object particles, float hPerSpacing) {
    const Particles p = particlesArg(particles, {}, hPerSpacing);
    const std::span<const glm::vec3> points(reinterpret_cast<const glm::vec3*>(p.position.data), p.size());
    pb::gil_scoped_release unlocked;
    return defaultRadiusOf(p, points).radius;
}

void writePngArray(const fs::path& path, pb::object image, pb::object alpha) {
    const pb::array a = pb::module_::import("numpy").attr("asarray")(image);
    if (a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4) || a.shape(0) < 1 || a.shape(1) < 1)
        throwValue("image: expected shape (H, W, 3) or (H, W, 4), got " + std::string(pb::str(a.attr("shape"))));
    if (a.dtype().kind() != 'u' || a.dtype().itemsize() != 1)
        throwValue("image: expected uint8 values (as render() returns), got " + std::string(pb::str(a.dtype())));
    const int h = int(a.shape(0)), w = int(a.shape(1)), c = int(a.shape(2));
    const bool withAlpha = alpha.is_none() ? c == 4 : alpha.cast<bool>();
    if (withAlpha && c == 3) throwValue("alpha=True needs an (H, W, 4) image");
    // Any layout: the writer takes its own RGBA copy anyway.
    const auto rgba = pb::array_t<std::uint8_t, pb::array::c_style | pb::array::forcecast>::ensure(a);
    Image<glm::u8vec4> img(w, h, glm::u8vec4(0, 0, 0, 255));
    const std::uint8_t* src = rgba.data();
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        for (int k = 0; k < c; ++k) img.pixels[i][k] = src[i * std::size_t(c) + std::size_t(k)];
    Status st = okStatus();
    {
        pb::gil_scoped_release unlocked;
        st = writePng(path, img, withAlpha);
    }
    if (!st) throwOs(st.error().describe());
}

}  // namespace

RadiusEstimate defaultRadiusOf(const Particles& p, std::span<const glm::vec3> points) {
    if (!p.radius.data) return estimateRadius(points);
    // The particles' own radii: defaultRadius takes their median, as the CLI
    // does for a file's radius attribute (this one case copies the arrays).
    ParticleSet set;
    set.positions.assign(points.begin(), points.end());
    set.attributes.push_back({p.radiusName.empty() ? std::string(kAttrRadiusNames[0]) : p.radiusName,
                              AttributeType::Float, 1,
                              std::vector<float>(p.radius.data, p.radius.data + p.size()), {}});
    return defaultRadius(set);
}

void bindRead(pb::module_& m) {
    m.def("read", &read, pb::arg("path"), pb::arg("allow_empty") = false,
          R"(Read one particle file (BGEO, VTK, VTU/VTP, PLY, CSV, XYZ; the format from the name).

Returns a dict of numpy arrays: "position" (N x 3 float32, metres) and every
attribute of the file under its canonical name: "velocity" (N x 3 float32),
"density" (N float32), "id" (N int64), and the others by their own name
(float attributes float32, integer ones int64; N x C when C > 1).
Particles with a non-finite position are dropped, as `meniscus render` drops
them, with a UserWarning saying how many. An empty file is an OSError unless
allow_empty (then every array has 0 rows).

Raises FileNotFoundError when the file does not exist and OSError when it
cannot be read or is not a valid particle file (the message names the file
and the problem).)");
    m.def("sequence", &sequence, pb::arg("spec"),
          R"(The frame files a sequence spec names, in order (as `meniscus render` takes them).

spec: a file (a .pvd collection: the files it lists, in time order), a
directory (every particle file in it), a printf pattern (frame_%04d.ply) or a
glob (ParticleData_Fluid_*.bgeo). Frames sort in natural numeric order.
Returns a list of paths (str). FileNotFoundError when nothing matches.)");
    m.def("demo", &demo,
          R"(The bundled demo frame (SPlisHSPlasH dam break, frame 21, r = 0.025 m) as read() returns it.

render(demo(), radius=DEMO_RADIUS) gives the image `meniscus demo` writes.)");
    m.attr("DEMO_RADIUS") = kDemoRadiusM;
    m.def("estimate_radius", &estimateRadiusOf, pb::arg("particles"), pb::kw_only(),
          pb::arg("h_per_spacing") = defaults::kHPerSpacing,
          R"(The particle radius render() and mesh() use when none is given, in metres.

particles: an N x 3 array of positions or a dict as read() returns it. The
median of the per-particle radii ("radius", "pscale", "particle_radius") when
the dict has them (or a smoothing length "h", "hsml", ...: radii
h / (2 h_per_spacing)), else estimated from the bulk number density of the
positions (docs/radius.md), as `meniscus info` reports it.)");
    m.def("write_png", &writePngArray, pb::arg("path"), pb::arg("image"), pb::arg("alpha") = pb::none(),
          R"(Write an 8-bit image (H x W x 3 or H x W x 4 uint8, row 0 at the top) as a PNG.

alpha: None writes RGBA for 4 channels and RGB for 3; False drops the alpha
channel, as `meniscus render` does for an image with the studio background
(so write_png(path, render(...), alpha=False) writes the CLI's file byte for
byte). Written to a temporary name and renamed. OSError when it cannot be
written.)");
}

}  // namespace meniscus::py
