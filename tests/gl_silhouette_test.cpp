// GL silhouette reduction (Cords & Staadt 2008, "Instant Liquids" §3;
// docs/pipeline.md#silhouette-reduction; src/gl/silhouette.cpp and
// shaders/silhouette_*.comp) against the CPU reference cpu::reduceSilhouettes: S
// and the faded colour bit for bit on a synthetic depth of an odd size (a disc
// whose depth varies across it, so the windows differ from pixel to pixel, a
// sheet 3 pixels wide, fluid touching all four borders, single scattered pixels)
// under scrambled colour and scene colour, for the fade from 0.5 and from 0, the
// paper's clip, a window of one pixel's half-width and one capped at maxPx;
// images of another size leave the colour and give S = 0; then the whole pipeline
// with the reduction on through the public Renderer on the real frame (the
// silhouette AOV and the depth the same bits, the colour within the
// whole-pipeline tolerance), and fading over the scene colour's own slot
// keeps the cached scene. Skips only when no headless GL 4.3 context can be
// created at all.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/backend.h"
#include "cpu/silhouette.h"
#include "gl/backend.h"
#include "render/stages.h"
#include "gl/gpu_image.h"
#include "gl/silhouette.h"
#include "gl_test_util.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "shared/kernel_radius.h"
#include "test_util.h"

namespace gl_silhouette_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlSilhouette : public GlTest {};

constexpr float kInf = std::numeric_limits<float>::infinity();


struct Scene {
    Camera camera;
    float radius = 0.015f;  // R = ceil(radiusRadii r f / z): 3 pixels at z = 1 on the 131-row image
    Image<float> depth;
    Image<glm::vec4> color, behind;
};

// W x H (odd sizes: a wrong row stride shows): a disc at 0.6-1.8 m (deeper
// to its right), a vertical sheet 3 pixels wide at 1.2 m, a block in the
// bottom-right corner and a band along the top-left borders, and ~1% of the
// rest single fluid pixels at 0.5-3 m; every pixel's colour and scene colour
// scrambled, with alpha 0, 0.4, 1 or scrambled.
Scene makeScene(int W, int H) {
    Scene s;
    s.camera = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, W, H);
    s.depth = Image<float>(W, H, kInf);
    const float cx = 0.35f * float(W), cy = 0.46f * float(H), rd = 0.23f * float(H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::uint32_t i = std::uint32_t(y * W + x);
            float z = kInf;
            if (std::hypot(float(x) + 0.5f - cx, float(y) + 0.5f - cy) < rd)
                z = 0.6f + 1.2f * (float(x) - (cx - rd)) / (2.0f * rd);
            else if (x >= int(0.7f * float(W)) && x < int(0.7f * float(W)) + 3 && y >= H / 12 && y < H - H / 12)
                z = 1.2f;
            else if (x >= int(0.8f * float(W)) && y >= int(0.7f * float(H)))
                z = 0.9f + 0.002f * float(x + y);
            else if (y < H / 16 && x < W / 3)
                z = 1.5f;
            else if (hash01(i, 1) < 0.01f)
                z = 0.5f + 2.5f * hash01(i, 2);
            s.depth.at(x, y) = z;
        }
    s.color = Image<glm::vec4>(W, H);
    s.behind = Image<glm::vec4>(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::uint32_t i = std::uint32_t(y * W + x);
            const float k = hash01(i, 3);
            const float a = k < 0.25f ? 0.0f : k < 0.5f ? 0.4f : k < 0.75f ? 1.0f : hash01(i, 4);
            s.color.at(x, y) = {hash01(i, 5), 2.0f * hash01(i, 6), hash01(i, 7), a};
            s.behind.at(x, y) = {hash01(i, 8), hash01(i, 9), 3.0f * hash01(i, 10), hash01(i, 11)};
        }
    return s;
}

struct Out {
    Image<float> s;
    Image<glm::vec4> color;
    double ms = 0.0;
};

Out runGl(const Scene& k, const SilhouetteParams& p) {
    Out o;
    static auto stage = gl::SilhouetteReduction::create();
    EXPECT_TRUE(stage.ok()) << stage.error().describe();
    if (!stage) return o;
    gl::GpuImage depth, behind, color, s;
    depth.upload(k.depth);
    behind.upload(k.behind);
    color.upload(k.color);
    glFinish();
    const auto t0 = std::chrono::steady_clock::now();
    stage->run(k.camera, depth, behind, k.radius, p, color, s);
    glFinish();
    o.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    o.s = s.download<float>();
    o.color = color.download<glm::vec4>();
    return o;
}

Out runCpu(const Scene& k, const SilhouetteParams& p) {
    Out o;
    o.color = k.color;
    const auto t0 = std::chrono::steady_clock::now();
    o.s = cpu::reduceSilhouettes(k.camera, k.depth, k.behind, k.radius, p, o.color);
    o.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return o;
}

// The CPU's and GL's S and colour bit for bit; at least `minFaded` pixels
// really faded (their colour changed) and some S strictly between 0 and 1.
void expectBitIdentical(const Scene& k, const SilhouetteParams& p, int minFaded, const char* what) {
    const Out ref = runCpu(k, p);
    (void)runGl(k, p);  // the first run pays llvmpipe's shader JIT
    const Out g = runGl(k, p);
    int faded = 0, partial = 0;
    for (std::size_t i = 0; i < ref.color.size(); ++i) {
        faded += std::memcmp(&ref.color.pixels[i], &k.color.pixels[i], sizeof(glm::vec4)) != 0;
        partial += ref.s.pixels[i] > 0.0f && ref.s.pixels[i] < 1.0f;
    }
    const int offS = differingBits(ref.s, g.s), offColor = differingBits(ref.color, g.color);
    std::printf("%s (%dx%d): %d pixels with 0 < S < 1, %d faded; differing S %d, colour %d (GL %.2f ms, CPU %.2f ms)\n",
                what, k.camera.width, k.camera.height, partial, faded, offS, offColor, g.ms, ref.ms);
    EXPECT_GE(faded, minFaded) << what;
    EXPECT_GT(partial, minFaded / 2) << what;
    EXPECT_EQ(offS, 0) << what;
    EXPECT_EQ(offColor, 0) << what;
    for (std::size_t i = 0; i < ref.s.size() && i < g.s.size() && offS + offColor > 0; ++i)
        if (std::memcmp(&ref.s.pixels[i], &g.s.pixels[i], 4) != 0 ||
            std::memcmp(&ref.color.pixels[i], &g.color.pixels[i], 16) != 0) {
            const std::size_t W = std::size_t(ref.s.width);
            ADD_FAILURE() << what << ": first difference at pixel " << i % W << ", " << i / W << ": cpu S "
                          << ref.s.pixels[i] << " gl " << g.s.pixels[i] << "; cpu r " << ref.color.pixels[i].r
                          << " gl " << g.color.pixels[i].r;
            break;
        }
}

int partialPixels(const Image<float>& s) {
    int n = 0;
    for (float v : s.pixels) n += v > 0.0f && v < 1.0f;
    return n;
}

}  // namespace

TEST_F(GlSilhouette, SAndTheFadedColourAreTheCpuBits) {
    const Scene k = makeScene(173, 131);
    SilhouetteParams p;
    p.enabled = true;
    // The scene really has what the test is about: windows of several sizes
    // (the depth varies), fluid on every border, single pixels.
    const int W = k.camera.width, H = k.camera.height;
    std::set<int> halfWidths;
    int singles = 0, onBorder[4] = {0, 0, 0, 0};
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (!(k.depth.at(x, y) < kInf)) continue;
            halfWidths.insert(shared::projectedRadiusPx(p.radiusRadii * k.radius, k.camera.focalPx(), k.depth.at(x, y),
                                                        p.maxPx));
            onBorder[0] += x == 0, onBorder[1] += x == W - 1, onBorder[2] += y == 0, onBorder[3] += y == H - 1;
            bool alone = true;
            for (int v = y - 1; v <= y + 1; ++v)
                for (int u = x - 1; u <= x + 1; ++u)
                    if ((u != x || v != y) && u >= 0 && u < W && v >= 0 && v < H) alone &= !(k.depth.at(u, v) < kInf);
            singles += alone;
        }
    EXPECT_GE(halfWidths.size(), 4u);
    EXPECT_GT(singles, 50);
    for (int b : onBorder) EXPECT_GT(b, 3);

    expectBitIdentical(k, p, 1000, "fade from 0.5");
    p.fadeFrom = 0.0f;
    expectBitIdentical(k, p, 1000, "fade from 0");
    p.fadeFrom = 1.0f;
    expectBitIdentical(k, p, 1000, "the clip (fade from 1)");
    p.fadeFrom = 0.7f;
    p.radiusRadii = 0.01f;  // ceil of a fraction of a pixel: a 3 x 3 window
    expectBitIdentical(k, p, 300, "radiusRadii 0.01");
    p.radiusRadii = 64.0f;  // far past the cap everywhere: every window maxPx wide
    p.maxPx = 9;
    expectBitIdentical(k, p, 3000, "radiusRadii 64, maxPx 9");
    // A larger image (for the timing), with the defaults.
    expectBitIdentical(makeScene(1280, 720), SilhouetteParams{true}, 10000, "defaults");
}

TEST_F(GlSilhouette, MismatchedImagesLeaveTheColourAndGiveSZero) {
    const Scene k = makeScene(173, 131);
    SilhouetteParams p;
    p.enabled = true;
    auto unchanged = [&](const Scene& m, const char* what) {
        const Out g = runGl(m, p);
        ASSERT_EQ(g.s.width, k.camera.width) << what;
        ASSERT_EQ(g.s.height, k.camera.height) << what;
        for (float v : g.s.pixels) ASSERT_EQ(v, 0.0f) << what;
        EXPECT_EQ(differingBits(m.color, g.color), 0) << what;
        const Out ref = runCpu(m, p);
        EXPECT_EQ(differingBits(ref.s, g.s), 0) << what;
        EXPECT_EQ(differingBits(ref.color, g.color), 0) << what;
    };
    ASSERT_GT(partialPixels(runGl(k, p).s), 500);  // the same scene at its own size does fade
    Scene depth = k;
    depth.depth = Image<float>(8, 8, 1.0f);
    unchanged(depth, "a depth of another size");
    Scene behind = k;
    behind.behind = Image<glm::vec4>(172, 131, glm::vec4(0.5f));
    unchanged(behind, "a scene colour of another size");
    Scene color = k;
    color.color = Image<glm::vec4>(173, 130, glm::vec4(0.25f));
    unchanged(color, "a colour of another size");
}

// The whole pipeline with the reduction on: the silhouette AOV and the depth
// the same bits, the colour within gl_backend_test's whole-pipeline
// tolerance (2 sRGB steps, at most 0.1% of the pixels off by more than 1).
TEST_F(GlSilhouette, PipelineWithSilhouetteMatchesCpuOnTheRealFrame) {
    const ParticleView view = ParticleView::of(realSet());
    ASSERT_GT(view.size(), 0u);
    auto gl = Renderer::create(BackendChoice::Gl);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    Renderer cpu;
    RenderSettings s = realFrameSettings(320, 180);
    s.silhouette.enabled = true;
    struct Case {
        const char* what;
        bool background, noise;
        float fadeFrom, radiusRadii;
    };
    for (const Case& k : {Case{"defaults", true, false, 0.5f, 1.0f},
                          Case{"the clip, no background", false, false, 1.0f, 1.0f},
                          Case{"fade from 0.2, 3 r, with the noise", true, true, 0.2f, 3.0f}}) {
        s.scene.background = k.background;
        s.noise.enabled = k.noise;
        s.silhouette.fadeFrom = k.fadeFrom;
        s.silhouette.radiusRadii = k.radiusRadii;
        BackendFrames f;
        ASSERT_TRUE(renderOnBoth(cpu, *gl, view, s, f));
        const Aovs *a = &f.cpu, *b = &f.gl;
        const std::vector<StageTime>& cpuTimes = f.cpuTimes;
        const std::vector<StageTime>& times = f.glTimes;
        ASSERT_FALSE(a->silhouette.empty()) << k.what;
        ASSERT_FALSE(b->silhouette.empty()) << k.what;
        const int partial = partialPixels(a->silhouette);
        EXPECT_GT(partial, 200) << k.what;
        EXPECT_EQ(differingBits(a->depth, b->depth), 0) << k.what;
        EXPECT_EQ(differingBits(a->silhouette, b->silhouette), 0) << k.what;
        const ColorDiff c = expectPipelineColor(a->color, b->color, k.what);
        const double glMs = stageMs(times, "silhouette"), cpuMs = stageMs(cpuTimes, "silhouette");
        EXPECT_GE(glMs, 0.0) << "no silhouette stage timed";
        std::printf("%s: %d pixels with 0 < S < 1; colour max %d steps, %.2g%% over 1; silhouette stage GL %.2f ms,"
                    " CPU %.2f ms\n",
                    k.what, partial, c.maxSteps, 100.0 * c.fractionOver1, glMs, cpuMs);
    }
}

// Faded over the scene colour's own slot (not the pipeline's order, but the
// backend interface allows it), toward another colour, the stage never
// changes the cached scene: the next cast gives the clean scene again, on
// both backends (GL: the stage drops the cache; CPU: it copies).
TEST_F(GlSilhouette, FadingTheSceneSlotKeepsTheCachedScene) {
    const std::vector<glm::vec3> block = jitteredBlock({12, 8, 2}, 0.03f, 0.2f, {0.1f, 0.15f, 0.6f}, 3);
    FrameSettings fs;
    fs.camera = faceOnCamera({0.3f, 0.3f, 0.3f}, 1.0f, 96, 64);
    fs.radius = 0.03f;
    fs.silhouette.enabled = true;
    fs.silhouette.fadeFrom = 1.0f;  // the clip: the block's rim becomes the other colour
    std::string why;
    ASSERT_TRUE(sharedGlContext(&why)->makeCurrent().ok());  // the Renderers above made their own current
    auto gl = gl::makeGlBackendOnCurrentContext();
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const std::unique_ptr<Backend> cpu = makeCpuBackend();
    const Image<glm::vec4> other(96, 64, glm::vec4(1.0f, 0.0f, 1.0f, 1.0f));
    for (Backend* b : {gl->get(), cpu.get()}) {
        ASSERT_TRUE(b->beginFrame(block, fs).ok()) << b->name();
        ASSERT_TRUE(runStage(*b, "scene", {}).ok()) << b->name();
        const Image<glm::vec4> clean = b->readColor(Slot::SceneColor);
        ASSERT_TRUE(runStage(*b, "depth-splat+thickness", {}).ok()) << b->name();
        b->writeColor(Slot::Color, other);
        StageIo io;  // the scene colour as the colour faded, another colour as the scene
        io.at.sceneColor = Slot::Color, io.at.depth = Slot::RawDepth, io.at.color = Slot::SceneColor;
        EXPECT_TRUE(runStage(*b, "silhouette", io).ok()) << b->name();
        EXPECT_GT(partialPixels(b->readScalar(Slot::Silhouette)), 50) << b->name();
        EXPECT_GT(differingBits(clean, b->readColor(Slot::SceneColor)), 50) << b->name();
        ASSERT_TRUE(runStage(*b, "scene", {}).ok()) << b->name();
        EXPECT_EQ(differingBits(clean, b->readColor(Slot::SceneColor)), 0) << b->name();
    }
}
}  // namespace gl_silhouette_test_local
