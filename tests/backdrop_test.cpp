// Backdrops (include/meniscus/backdrop.h, docs/compositing.md): the depth
// conventions against their formulas, the reader on EXR files written here
// (plain and Blender's multilayer channel names, a separate depth file, the
// errors), and the compositing: the studio's own layer given as a backdrop
// renders the same picture as the studio, and a backdrop nearer than the
// liquid hides it.
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <gtest/gtest.h>

#include "core/backdrop_layer.h"
#include "cpu/scene.h"
#include "meniscus/backdrop.h"
#include "meniscus/io.h"
#include "meniscus/options.h"
#include "meniscus/renderer.h"
#include "shared/backdrop.h"
#include "shared/studio.h"
#include "test_util.h"

namespace backdrop_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// An EXR of float channels (each width x height values, row 0 at the top);
// `shift` moves the data window off the display window.
void writeExr(const std::filesystem::path& p, int w, int h, const std::map<std::string, std::vector<float>>& channels,
              int shift = 0) {
    Imf::Header header(w, h);
    if (shift) header.dataWindow() = Imath::Box2i({shift, 0}, {w - 1 + shift, h - 1});
    for (const auto& [name, v] : channels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(p.string().c_str(), header);
    Imf::FrameBuffer fb;
    for (const auto& [name, v] : channels)
        fb.insert(name, Imf::Slice(Imf::FLOAT, (char*)(v.data() - shift), sizeof(float), sizeof(float) * w));
    file.setFrameBuffer(fb);
    file.writePixels(h);
}

std::vector<float> ramp(int n, float a, float b) {
    std::vector<float> v(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) v[std::size_t(i)] = a + b * float(i);
    return v;
}

}  // namespace

TEST(BackdropDepth, ParsesTheKindsAndRefusesTheRest) {
    EXPECT_EQ(parseBackdropDepth("linear")->kind, BackdropDepthKind::Linear);
    EXPECT_EQ(parseBackdropDepth("ray")->kind, BackdropDepthKind::Ray);
    EXPECT_EQ(parseBackdropDepth("blender")->kind, BackdropDepthKind::Blender);
    auto w = parseBackdropDepth("window:0.1,100");
    ASSERT_TRUE(w);
    EXPECT_EQ(w->kind, BackdropDepthKind::Window);
    EXPECT_FLOAT_EQ(w->nearM, 0.1f);
    EXPECT_FLOAT_EQ(w->farM, 100.0f);
    EXPECT_EQ(backdropDepthText(*w), "window:0.1,100");
    for (const char* bad : {"", "Linear", "window", "window:1", "window:2,1", "window:0,1", "window:a,b",
                            "window:1,2x", "window:-1,2", "window:1,inf"}) {
        auto r = parseBackdropDepth(bad);
        EXPECT_FALSE(r) << bad;
        if (!r) {
            EXPECT_NE(r.error().message.find("window:NEAR,FAR"), std::string::npos);
        }
    }
}

// Each kind's value of a point at eye depth z comes back as z: the ray
// distance z |d|, a GL projection's window depth, and the planar values.
TEST(BackdropDepth, EachKindGivesTheEyeDepthBack) {
    Camera cam;
    cam.width = 64, cam.height = 48, cam.fovYDegrees = 60.0f;
    const float n = 0.05f, f = 50.0f;
    for (float z : {0.07f, 0.5f, 1.0f, 3.7f, 20.0f, 49.0f})
        for (glm::vec2 px : {glm::vec2(0.5f, 0.5f), glm::vec2(32.5f, 24.5f), glm::vec2(63.5f, 10.5f)}) {
            const float len = glm::length(cam.pixelRay(px.x, px.y));
            EXPECT_EQ(shared::backdropEyeDepth(z, shared::kBackdropLinear, len, 0, 0), z);
            EXPECT_EQ(shared::backdropEyeDepth(z, shared::kBackdropBlender, len, 0, 0), z);
            const glm::vec3 point = z * cam.pixelRay(px.x, px.y);
            EXPECT_NEAR(shared::backdropEyeDepth(glm::length(point), shared::kBackdropRay, len, 0, 0), z, 2e-6f * z);
            // The GL perspective matrix's depth of view-space z = -z, then to [0, 1].
            const double ndc = (double(f) + n) / (double(f) - n) - 2.0 * f * n / ((double(f) - n) * z);
            const float window = float(0.5 * ndc + 0.5);
            EXPECT_NEAR(shared::backdropEyeDepth(window, shared::kBackdropWindow, len, n, f), z, 2e-3f * z * z);
        }
    // Nothing: a renderer's background, and values that are no depth.
    for (float raw : {kInf, -kInf, std::nanf(""), 0.0f, -1.0f, 1e10f})
        EXPECT_EQ(shared::backdropEyeDepth(raw, shared::kBackdropBlender, 1.0f, 0, 0), kInf) << raw;
    for (float raw : {1.0f, 1.5f, -0.1f, std::nanf("")})
        EXPECT_EQ(shared::backdropEyeDepth(raw, shared::kBackdropWindow, 1.0f, n, f), kInf) << raw;
    EXPECT_FLOAT_EQ(shared::backdropEyeDepth(0.0f, shared::kBackdropWindow, 1.0f, n, f), n);
}

TEST(BackdropReader, ReadsColourAlphaAndZ) {
    const auto dir = tempDir() / "backdrop_plain";
    std::filesystem::create_directories(dir);
    const int w = 5, h = 3, n = w * h;
    writeExr(dir / "set.exr", w, h,
             {{"R", ramp(n, 0.1f, 0.01f)}, {"G", ramp(n, 0.2f, 0.0f)}, {"B", ramp(n, 0.3f, 0.02f)},
              {"A", ramp(n, 1.0f, 0.0f)}, {"Z", ramp(n, 1.0f, 0.5f)}});
    auto b = readBackdrop(dir / "set.exr", {}, *parseBackdropDepth("ray"));
    ASSERT_TRUE(b) << b.error().describe();
    EXPECT_EQ(b->width, w);
    EXPECT_EQ(b->height, h);
    ASSERT_EQ(b->color.size(), std::size_t(n));
    ASSERT_EQ(b->depth.size(), std::size_t(n));
    EXPECT_EQ(b->convention.kind, BackdropDepthKind::Ray);
    EXPECT_FLOAT_EQ(b->color[7].r, 0.1f + 0.07f);
    EXPECT_FLOAT_EQ(b->color[7].b, 0.3f + 0.14f);
    EXPECT_FLOAT_EQ(b->color[7].a, 1.0f);
    EXPECT_FLOAT_EQ(b->depth[14], 1.0f + 7.0f);
}

// Blender's multilayer EXR: "ViewLayer.Combined.R", "ViewLayer.Depth.Z", and
// other passes whose last part is also a colour (its normal pass's X Y Z
// are not R G B, but a "Denoising Albedo" layer's R G B are).
TEST(BackdropReader, FindsBlendersLayeredChannels) {
    const auto dir = tempDir() / "backdrop_blender";
    std::filesystem::create_directories(dir);
    const int w = 4, h = 2, n = w * h;
    std::map<std::string, std::vector<float>> ch = {
        {"ViewLayer.Combined.R", ramp(n, 0.5f, 0.0f)},   {"ViewLayer.Combined.G", ramp(n, 0.25f, 0.0f)},
        {"ViewLayer.Combined.B", ramp(n, 0.125f, 0.0f)}, {"ViewLayer.Combined.A", ramp(n, 1.0f, 0.0f)},
        {"ViewLayer.Depth.Z", ramp(n, 2.0f, 1.0f)},      {"ViewLayer.Normal.Z", ramp(n, -1.0f, 0.0f)},
        {"ViewLayer.DiffCol.R", ramp(n, 9.0f, 0.0f)},    {"ViewLayer.DiffCol.G", ramp(n, 9.0f, 0.0f)},
        {"ViewLayer.DiffCol.B", ramp(n, 9.0f, 0.0f)}};
    writeExr(dir / "multilayer.exr", w, h, ch);
    auto b = readBackdrop(dir / "multilayer.exr", {}, *parseBackdropDepth("blender"));
    ASSERT_TRUE(b) << b.error().describe();
    EXPECT_FLOAT_EQ(b->color[3].r, 0.5f);
    EXPECT_FLOAT_EQ(b->color[3].b, 0.125f);
    EXPECT_FLOAT_EQ(b->depth[3], 5.0f);
    // Without a Combined layer the two colour passes are ambiguous: named.
    ch.erase("ViewLayer.Combined.R");
    ch["ViewLayer.Other.R"] = ramp(n, 0.0f, 0.0f);
    writeExr(dir / "ambiguous.exr", w, h, ch);
    auto a = readBackdrop(dir / "ambiguous.exr", {}, {});
    ASSERT_FALSE(a);
    EXPECT_NE(a.error().message.find("several channels could be R"), std::string::npos) << a.error().message;
    EXPECT_NE(a.error().message.find("ViewLayer.DiffCol.R"), std::string::npos);
}

TEST(BackdropReader, TakesTheDepthFromItsOwnFile) {
    const auto dir = tempDir() / "backdrop_two_files";
    std::filesystem::create_directories(dir);
    const int w = 3, h = 2, n = w * h;
    writeExr(dir / "rgb.exr", w, h, {{"R", ramp(n, 0, 0)}, {"G", ramp(n, 0, 0)}, {"B", ramp(n, 0, 0)}});
    writeExr(dir / "y.exr", w, h, {{"Y", ramp(n, 3.0f, 1.0f)}});
    auto b = readBackdrop(dir / "rgb.exr", dir / "y.exr", {});
    ASSERT_TRUE(b) << b.error().describe();
    EXPECT_FLOAT_EQ(b->depth[5], 8.0f);
    EXPECT_FLOAT_EQ(b->color[0].a, 1.0f);  // no alpha: opaque
    // A colour EXR without Z and no depth file: the error says how to give one.
    auto noZ = readBackdrop(dir / "rgb.exr", {}, {});
    ASSERT_FALSE(noZ);
    EXPECT_NE(noZ.error().message.find("--backdrop-depth"), std::string::npos) << noZ.error().message;
    EXPECT_EQ(noZ.error().file, (dir / "rgb.exr").string());
    // Another size.
    writeExr(dir / "small.exr", 2, 2, {{"Z", ramp(4, 1, 0)}});
    auto other = readBackdrop(dir / "rgb.exr", dir / "small.exr", {});
    ASSERT_FALSE(other);
    EXPECT_NE(other.error().message.find("2x2"), std::string::npos) << other.error().message;
    // Several channels, none of them Z.
    writeExr(dir / "uv.exr", w, h, {{"U", ramp(n, 0, 0)}, {"V", ramp(n, 0, 0)}});
    auto uv = readBackdrop(dir / "rgb.exr", dir / "uv.exr", {});
    ASSERT_FALSE(uv);
    EXPECT_NE(uv.error().message.find("U, V"), std::string::npos) << uv.error().message;
}

TEST(BackdropReader, RefusesWhatItCannotUse) {
    const auto dir = tempDir() / "backdrop_bad";
    std::filesystem::create_directories(dir);
    const auto expectError = [](const Result<BackdropImage>& r, const std::filesystem::path& file, const char* what) {
        ASSERT_FALSE(r) << what;
        EXPECT_EQ(r.error().file, file.string()) << what;
        EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().message;
    };
    expectError(readBackdrop(dir / "none.exr", {}, {}), dir / "none.exr", "no such file");
    writeText(dir / "garbage.exr", "not an image at all");
    expectError(readBackdrop(dir / "garbage.exr", {}, {}), dir / "garbage.exr", "not a readable picture");
    writeText(dir / "set.tif", "II*");
    expectError(readBackdrop(dir / "set.tif", {}, {}), dir / "set.tif", "not an OpenEXR");
    writeText(dir / "set.png", "x");
    expectError(readBackdrop(dir / "set.png", {}, {}), dir / "set.png", "holds no depth");
    writeExr(dir / "cropped.exr", 4, 2,
             {{"R", ramp(8, 0, 0)}, {"G", ramp(8, 0, 0)}, {"B", ramp(8, 0, 0)}, {"Z", ramp(8, 1, 0)}}, 1);
    expectError(readBackdrop(dir / "cropped.exr", {}, {}), dir / "cropped.exr", "data window");
    writeExr(dir / "grey.exr", 2, 2, {{"Y", ramp(4, 0, 0)}, {"Z", ramp(4, 1, 0)}});
    expectError(readBackdrop(dir / "grey.exr", {}, {}), dir / "grey.exr", "no R channel");
}

TEST(BackdropReader, ArraysAreCheckedAsFilesAre) {
    std::vector<float> rgb(2 * 3 * 3, 0.5f), depth(6, 1.0f);
    rgb[4] = std::nanf("");
    auto b = makeBackdrop(3, 2, rgb, 3, depth, {});
    ASSERT_TRUE(b) << b.error().describe();
    EXPECT_EQ(b->color[1].g, 0.0f);  // a NaN colour is 0
    EXPECT_FALSE(makeBackdrop(3, 2, rgb, 4, depth, {}));
    EXPECT_FALSE(makeBackdrop(3, 2, rgb, 3, std::vector<float>(5), {}));
    EXPECT_FALSE(makeBackdrop(0, 2, {}, 3, {}, {}));
    EXPECT_FALSE(makeBackdrop(kMaxBackdropSidePx + 1, 1, rgb, 3, depth, {}));
}

namespace {

// The frame and settings of the compositing tests: frame 21 seen by the
// automatic camera at 160 x 120, its studio built around a fixed box.
struct Shot {
    ParticleSet set;
    RenderSettings settings;
};

Shot shot() {
    Shot s;
    s.set = smallFrame21();
    s.settings = autoFramedSettings(s.set, 160, 120);
    Bounds box;
    for (const glm::vec3& p : s.set.positions) box.extend(p);
    s.settings.scene.studioBounds = box;
    return s;
}

// The studio's own layer (what the scene stage casts for `s`) as a backdrop of
// `kind`: colour and alpha as they are, depth as that kind writes it.
std::shared_ptr<const BackdropImage> studioAsBackdrop(const RenderSettings& s, const std::string& kind) {
    const shared::Studio studio =
        shared::makeStudio(s.scene.studioBounds, s.radiusM, s.camera, s.scene, s.shading.lightDirWorld);
    const cpu::SceneLayer layer = cpu::castScene(s.camera, studio);
    std::vector<float> rgba, depth;
    for (int y = 0; y < s.camera.height; ++y)
        for (int x = 0; x < s.camera.width; ++x) {
            const glm::vec4 c = layer.color.at(x, y);
            rgba.insert(rgba.end(), {c.r, c.g, c.b, c.a});
            const float z = layer.depth.at(x, y);
            depth.push_back(kind == "ray" ? z * glm::length(s.camera.pixelRay(x + 0.5f, y + 0.5f)) : z);
        }
    auto b = makeBackdrop(s.camera.width, s.camera.height, rgba, 4, depth, *parseBackdropDepth(kind));
    EXPECT_TRUE(b) << b.error().describe();
    return std::make_shared<const BackdropImage>(std::move(*b));
}

}  // namespace

// Composited exactly as over the studio: the studio's own colour and depth
// given as a backdrop (linear eye depth) render the same bits, liquid and
// all; as ray distances, the same picture within rounding.
TEST(Backdrop, TheStudiosOwnLayerRendersAsTheStudio) {
    const Shot s = shot();
    Renderer cpu;
    auto studio = cpu.render(ParticleView::of(s.set), s.settings);
    ASSERT_TRUE(studio) << studio.error().describe();
    RenderSettings withBackdrop = s.settings;
    withBackdrop.scene.backdrop = studioAsBackdrop(s.settings, "linear");
    Renderer other;
    auto b = other.render(ParticleView::of(s.set), withBackdrop);
    ASSERT_TRUE(b) << b.error().describe();
    EXPECT_EQ(differingBits(studio->color, b->color), 0);
    EXPECT_EQ(differingBits(studio->depth, b->depth), 0);
    withBackdrop.scene.backdrop = studioAsBackdrop(s.settings, "ray");
    auto r = other.render(ParticleView::of(s.set), withBackdrop);
    ASSERT_TRUE(r) << r.error().describe();
    float worst = 0.0f;
    for (std::size_t i = 0; i < r->color.size(); ++i)
        worst = std::max(worst, glm::length(glm::vec3(r->color.pixels[i] - studio->color.pixels[i])));
    EXPECT_LT(worst, 1e-3f);
}

// A set nearer than the liquid hides it: where the backdrop's depth lies
// in front, its colour is the picture and nothing of the liquid is covered;
// elsewhere (nothing there) the liquid is drawn over the backdrop's colour.
TEST(Backdrop, ANearerSetHidesTheLiquid) {
    const Shot s = shot();
    const int W = s.settings.camera.width, H = s.settings.camera.height;
    Renderer cpu;
    auto plain = cpu.render(ParticleView::of(s.set), s.settings);
    ASSERT_TRUE(plain);
    float nearest = kInf;  // the liquid's nearest point; the set stands halfway to it
    for (float z : plain->rawDepth.pixels) nearest = std::min(nearest, z);
    ASSERT_TRUE(std::isfinite(nearest));
    const float setDepth = std::max(0.5f * nearest, 1.01f * s.settings.camera.nearM);
    ASSERT_LT(setDepth, nearest);
    std::vector<float> rgb, depth;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            rgb.insert(rgb.end(), {0.8f, 0.1f, 0.1f});
            depth.push_back(x < W / 2 ? setDepth : kInf);
        }
    RenderSettings set = s.settings;
    set.scene.backdrop = std::make_shared<const BackdropImage>(*makeBackdrop(W, H, rgb, 3, depth, {}));
    auto b = cpu.render(ParticleView::of(s.set), set);
    ASSERT_TRUE(b) << b.error().describe();
    int liquidLeft = 0, liquidRight = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const bool liquid = std::isfinite(plain->depth.at(x, y));
            if (x < W / 2) {
                liquidLeft += liquid;
                EXPECT_EQ(b->color.at(x, y), glm::vec4(0.8f, 0.1f, 0.1f, 1.0f)) << x << "," << y;
                EXPECT_FALSE(std::isfinite(b->depth.at(x, y)));
            } else if (liquid) {
                ++liquidRight;
                EXPECT_TRUE(std::isfinite(b->depth.at(x, y)));
                EXPECT_NE(b->color.at(x, y), glm::vec4(0.8f, 0.1f, 0.1f, 1.0f));
            }
        }
    EXPECT_GT(liquidLeft, 100);  // the test hides liquid that is there
    EXPECT_GT(liquidRight, 100);
}

TEST(Backdrop, ItsSizeMustBeThePictures) {
    const Shot s = shot();
    RenderSettings set = s.settings;
    set.scene.backdrop = std::make_shared<const BackdropImage>(
        *makeBackdrop(8, 4, std::vector<float>(8 * 4 * 3), 3, std::vector<float>(32, 1.0f), {}));
    Renderer cpu;
    auto r = cpu.render(ParticleView::of(s.set), set);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("8x4 pixels and the picture 160x120"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("--width 8 --height 4"), std::string::npos);
}

// The options: files read through renderSettings, errors naming the option.
TEST(Backdrop, OptionsReadTheFiles) {
    const auto dir = tempDir() / "backdrop_options";
    std::filesystem::create_directories(dir);
    const int w = 16, h = 9, n = w * h;
    writeExr(dir / "set.exr", w, h,
             {{"R", ramp(n, 0, 0)}, {"G", ramp(n, 0, 0)}, {"B", ramp(n, 0, 0)}, {"Z", ramp(n, 1, 0)}});
    RenderOptions o;
    o.width = w, o.height = h;
    o.backdrop = (dir / "set.exr").string();
    o.backdropDepthKind = "window:0.1,10";
    auto s = renderSettings(o);
    ASSERT_TRUE(s) << s.error().describe();
    ASSERT_TRUE(s->scene.backdrop);
    EXPECT_EQ(s->scene.backdrop->convention.kind, BackdropDepthKind::Window);
    o.width = 32;
    auto wrongSize = renderSettings(o);
    ASSERT_FALSE(wrongSize);
    EXPECT_TRUE(wrongSize.error().usage);
    EXPECT_NE(wrongSize.error().message.find("--backdrop: the backdrop is 16x9"), std::string::npos);
    o.width = w;
    o.backdropDepthKind = "depth";
    auto badKind = renderSettings(o);
    ASSERT_FALSE(badKind);
    EXPECT_TRUE(badKind.error().usage);
    o.backdropDepthKind = "linear";
    o.backdrop = (dir / "missing.exr").string();
    auto missing = renderSettings(o);
    ASSERT_FALSE(missing);
    EXPECT_FALSE(missing.error().usage);
    EXPECT_EQ(missing.error().file, o.backdrop);
}
}  // namespace backdrop_test_local
