// The viewer's window (gl::Window, GLFW) and the GL backend presenting into it:
// a small synthetic frame rendered on the window's context and drawn into its
// default framebuffer must read back (glReadPixels) as the 8-bit sRGB values a
// PNG of the same frame holds; `meniscus view` shows what `meniscus render`
// writes. These need a display: CI runs this binary under `xvfb-run -a`
// (tests/CMakeLists.txt); elsewhere without one they skip, saying so. The
// error paths need no display and always run.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "gl/window.h"
#include "gl_test_util.h"
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/renderer.h"
#include "test_util.h"

using namespace meniscus;
using namespace meniscus::test;

namespace {

// Tolerances, in 8-bit sRGB steps per channel:
//  - presented vs the same GL frame encoded as the PNG writer does: 1 (the
//    shader evaluates the sRGB curve in float, the writer in double; only a
//    value within ~1e-6 of a rounding boundary can differ) on at most 0.1% of
//    the channels;
//  - presented vs the CPU backend's frame: 1, the GL parity of this small
//    frame (the real frame's 2-step outliers in gl_backend_test come from
//    thick, highlighted regions this frame does not have).
constexpr int kStepsVsGl = 1;
constexpr double kFractionOffVsGl = 1e-3;
constexpr int kStepsVsCpu = 1;

// Largest channel difference (RGB) and the fraction of channels that differ.
struct ByteDiff {
    int maxSteps = 0;
    double fractionDiffering = 0.0;
};
ByteDiff compareRgb(const Image<glm::u8vec4>& shown, const Image<glm::vec4>& linear) {
    ByteDiff d;
    EXPECT_EQ(shown.width, linear.width);
    EXPECT_EQ(shown.height, linear.height);
    std::size_t differing = 0, channels = 0;
    for (std::size_t k = 0; k < shown.size() && k < linear.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            const int steps = std::abs(int(shown.pixels[k][c]) - srgb8(linear.pixels[k][c]));
            d.maxSteps = std::max(d.maxSteps, steps);
            differing += steps != 0;
            ++channels;
        }
    d.fractionDiffering = channels ? double(differing) / double(channels) : 0.0;
    return d;
}

// A small block of liquid on the studio floor, auto-framed at w x h.
struct Frame {
    std::vector<glm::vec3> positions;
    RenderSettings settings;
};
Frame syntheticFrame(int w, int h) {
    Frame f;
    f.positions = jitteredBlock({10, 6, 8}, 0.05f, 0.2f, {0.0f, 0.0f, 0.0f});
    f.settings.radiusM = 0.025f;
    Camera base;
    base.width = w;
    base.height = h;
    f.settings.camera = autoFrameCamera(f.positions, f.settings.radiusM, base);
    return f;
}

// Each test opens its own window; skipped when none can be opened.
class GlWindow : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
            GTEST_SKIP() << "no display (DISPLAY unset); CI runs this test under xvfb-run -a";
        auto w = gl::Window::create(160, 120, "meniscus gl_window_test");
        if (!w) GTEST_SKIP() << "no window: " << w.error().describe();
        window_ = std::move(*w);
        std::printf("window GL: %s | %s\n", window_->renderer().c_str(), window_->version().c_str());
        auto r = Renderer::createOnCurrentGlContext();
        ASSERT_TRUE(r.ok()) << r.error().describe();
        renderer_.emplace(std::move(*r));
    }
    void TearDown() override {
        renderer_.reset();  // before the window: its GL objects live in the window's context
        window_.reset();
    }

    std::unique_ptr<gl::Window> window_;
    std::optional<Renderer> renderer_;
};

}  // namespace

// The frame drawn into the window reads back as the PNG writer would encode
// the GL backend's own colour, and within kStepsVsCpu of the CPU reference;
// row 0 of the read-back is the top (the studio floor is at the bottom).
TEST_F(GlWindow, PresentsTheFrameAsThePngWriterEncodesIt) {
    const glm::ivec2 size = window_->framebufferSize();
    ASSERT_GT(size.x, 0);
    const Frame f = syntheticFrame(size.x, size.y);
    ASSERT_TRUE(renderer_->draw(f.positions, f.settings).ok());
    ASSERT_TRUE(renderer_->present(size.x, size.y).ok());
    const Image<glm::u8vec4> shown = window_->readPixels();
    window_->swapBuffers();

    auto gl = renderer_->render(f.positions, f.settings);
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    const ByteDiff vsGl = compareRgb(shown, gl->color);
    EXPECT_LE(vsGl.maxSteps, kStepsVsGl);
    EXPECT_LE(vsGl.fractionDiffering, kFractionOffVsGl);

    auto cpu = Renderer().render(f.positions, f.settings);
    ASSERT_TRUE(cpu.ok()) << cpu.error().describe();
    const ByteDiff vsCpu = compareRgb(shown, cpu->color);
    EXPECT_LE(vsCpu.maxSteps, kStepsVsCpu);
    std::printf("  presented vs GL colour: max %d steps (%.4f%% of channels differ); vs CPU: max %d steps\n",
                vsGl.maxSteps, 100.0 * vsGl.fractionDiffering, vsCpu.maxSteps);

    // Not a flipped or blank copy: the top row (sky) and bottom row (floor) differ.
    EXPECT_NE(shown.at(size.x / 2, 0), shown.at(size.x / 2, size.y - 1));
}

// A debug view is drawn on the host and presented the same way.
TEST_F(GlWindow, PresentsDebugViews) {
    const glm::ivec2 size = window_->framebufferSize();
    Frame f = syntheticFrame(size.x, size.y);
    f.settings.view = View::Normals;
    ASSERT_TRUE(renderer_->draw(f.positions, f.settings).ok());
    ASSERT_TRUE(renderer_->present(size.x, size.y).ok());
    const Image<glm::u8vec4> shown = window_->readPixels();
    auto gl = renderer_->render(f.positions, f.settings);
    ASSERT_TRUE(gl.ok());
    EXPECT_LE(compareRgb(shown, gl->color).maxSteps, kStepsVsGl);
}

// An image smaller than the framebuffer (a resize not rendered yet) sits at
// the top-left; the rest is black.
TEST_F(GlWindow, ASmallerImageSitsAtTheTopLeft) {
    const glm::ivec2 size = window_->framebufferSize();
    const int w = size.x / 2, h = size.y / 2;
    const Frame f = syntheticFrame(w, h);
    ASSERT_TRUE(renderer_->draw(f.positions, f.settings).ok());
    ASSERT_TRUE(renderer_->present(size.x, size.y).ok());
    const Image<glm::u8vec4> shown = window_->readPixels();
    auto gl = renderer_->render(f.positions, f.settings);
    ASSERT_TRUE(gl.ok());
    Image<glm::u8vec4> corner(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) corner.at(x, y) = shown.at(x, y);
    EXPECT_LE(compareRgb(corner, gl->color).maxSteps, kStepsVsGl);
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            if (x < w && y < h) continue;
            ASSERT_EQ(glm::ivec3(shown.at(x, y)), glm::ivec3(0)) << x << "," << y;
        }
}

// `meniscus view --frames 3 --screenshot` exits 0 and saves what it showed:
// `meniscus render --backend gl` of the same input and options within 1 step
// (the same GL colour, encoded in float by the shader and in double by the
// writer); the demo frame with no input likewise.
TEST_F(GlWindow, ViewCommandShowsWhatRenderWrites) {
    const auto dir = tempDir();
    const std::string in = testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string();
    const std::string opts = " --width 160 --height 90 --filter curvature-flow --material milk";
    struct Case {
        std::string view, render;
    };
    const Case cases[] = {
        {"view " + in + opts, "render " + in + opts},
        {"view --width 128 --height 72", "demo --width 128 --height 72"},
    };
    for (const Case& c : cases) {
        std::string out;
        const auto shot = dir / "shown.png", written = dir / "written.png";
        ASSERT_EQ(runCommand(cliPath() + " " + c.view + " --frames 3 --screenshot " + shot.string(), &out), 0) << out;
        ASSERT_EQ(runCommand(cliPath() + " " + c.render + " --backend gl -o " + written.string(), &out), 0) << out;
        const PngData a = readPng(shot), b = readPng(written);
        ASSERT_EQ(a.width, b.width) << c.view;
        ASSERT_EQ(a.height, b.height);
        ASSERT_EQ(a.bytes.size(), b.bytes.size());
        ASSERT_FALSE(a.bytes.empty());
        int worst = 0;
        for (std::size_t k = 0; k < a.bytes.size(); ++k)
            worst = std::max(worst, std::abs(int(a.bytes[k]) - int(b.bytes[k])));
        EXPECT_LE(worst, 1) << c.view;
    }
}

// ---- Error paths: no display needed.

// Without a display, create() returns an error carrying GLFW's reason; it
// neither throws nor exits.
TEST(GlWindowErrors, CreateWithoutADisplayIsAnError) {
    const char* display = std::getenv("DISPLAY");
    const std::string saved = display ? display : "";
    ::unsetenv("DISPLAY");
    auto w = gl::Window::create(64, 64, "no display");
    if (display) ::setenv("DISPLAY", saved.c_str(), 1);
    ASSERT_FALSE(w.ok());
    const std::string msg = w.error().describe();
    EXPECT_NE(msg.find("cannot open a window"), std::string::npos) << msg;
    EXPECT_NE(msg.find("DISPLAY"), std::string::npos) << "GLFW's own reason: " << msg;
}

// Only a renderer on a window's context can present.
TEST(GlWindowErrors, OnlyAWindowRendererCanPresent) {
    Renderer cpu;
    const Status st = cpu.present(64, 64);
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("CPU"), std::string::npos) << st.error().describe();
}

// A renderer "on the current context" with no context current says so.
TEST(GlWindowErrors, NoCurrentContextIsAnError) {
    auto r = Renderer::createOnCurrentGlContext();
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().describe().find("4.3"), std::string::npos) << r.error().describe();
}
