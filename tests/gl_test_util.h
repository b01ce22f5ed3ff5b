// Helpers for the GL parity tests (gl_*_test.cpp): one headless context per test
// binary, a fixture that skips with the reason only when no GL 4.3 context can
// be created at all, and GL-vs-CPU comparisons in the units the tests state
// their tolerances in (relative depth, normal angle, 8-bit sRGB steps).
#pragma once

#include <cstring>
#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include "gl/context.h"
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/types.h"
#include "test_util.h"

namespace meniscus::test {

// One context for the whole binary (creating one per test costs ~50 ms on llvmpipe).
inline gl::Context* sharedGlContext(std::string* why) {
    static Result<std::unique_ptr<gl::Context>> ctx = [] {
        auto c = gl::Context::createHeadless();
        if (c)
            std::printf("GL renderer: %s | %s (EGL %s)\n", (*c)->renderer().c_str(), (*c)->version().c_str(),
                        (*c)->platform().c_str());
        return c;
    }();
    if (!ctx) {
        *why = ctx.error().describe();
        return nullptr;
    }
    return ctx->get();
}

// Base fixture of every GL test: the context is current, or the test is
// skipped. Made current again for each test: a test's own Renderer makes its
// context current and releases it when it goes, leaving none current for the
// tests after it in the same process.
class GlTest : public ::testing::Test {
protected:
    void SetUp() override {
        std::string why;
        gl::Context* ctx = sharedGlContext(&why);
        if (!ctx) GTEST_SKIP() << "no GL context: " << why;
        if (auto st = ctx->makeCurrent(); !st) GTEST_SKIP() << "the GL context cannot be made current: " << st.error().describe();
        // The stages' parity tests compare bit-identical inputs: the GL
        // backend takes the host's ellipsoids, as the CPU backend. The tests
        // of its own (gl/anisotropy.h: gl_anisotropy_test, and the pipeline
        // with them) set this to 0.
        setenv("MENISCUS_GL_HOST_ANISOTROPY", "1", 1);
    }
};

// ---- The real frame every parity test uses --------------------------------
// tests/data/splishsplash/partio/ParticleData_Fluid_21.bgeo (a SPlisHSPlasH
// dam break), read once per test binary, with its estimated particle radius.
struct RealFrame {
    std::vector<glm::vec3> positions;
    float radius = 0.0f;
};
inline const RealFrame& realFrame() {
    static const RealFrame frame = [] {
        RealFrame f;
        auto set = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
        EXPECT_TRUE(set.ok()) << set.error().describe();
        if (set) {
            f.positions = set->positions;
            f.radius = estimateRadius(f.positions).radius;
        }
        return f;
    }();
    return frame;
}
// The auto-framed camera of the real frame at w x h pixels.
inline Camera realFrameCamera(int w, int h) {
    Camera base;
    base.width = w;
    base.height = h;
    return autoFrameCamera(realFrame().positions, realFrame().radius, base);
}

// ---- Depth (eye depth, +inf = no fluid) -------------------------------------
struct DepthDiff {
    int coveredCpu = 0;      // pixels with fluid on the CPU
    int coverageDiffer = 0;  // fluid on one side only
    double maxRel = 0.0;     // max |gl - cpu| / cpu where both have fluid
    double meanRel = 0.0;
};
inline DepthDiff compareDepth(const Image<float>& cpu, const Image<float>& gl) {
    DepthDiff d;
    EXPECT_EQ(cpu.width, gl.width);
    EXPECT_EQ(cpu.height, gl.height);
    double sum = 0.0;
    int both = 0;
    for (std::size_t k = 0; k < cpu.size() && k < gl.size(); ++k) {
        const float a = cpu.pixels[k], b = gl.pixels[k];
        const bool fa = std::isfinite(a), fb = std::isfinite(b);
        d.coveredCpu += fa;
        if (fa != fb) {
            ++d.coverageDiffer;
            continue;
        }
        if (!fa) continue;
        const double rel = std::abs(double(b) - double(a)) / std::abs(double(a));
        d.maxRel = std::max(d.maxRel, rel);
        sum += rel;
        ++both;
    }
    d.meanRel = both ? sum / both : 0.0;
    return d;
}

// The depth where the inputs differ by rounding (the GL backend's own
// ellipsoids, gl/anisotropy.h, in float against the CPU's in double): a
// grazing ray may meet another ellipsoid, and the smoothing spreads that, so
// instead of a bound on every pixel at most `fraction` of the covered pixels
// may differ by more than `rel`, and none by more than `cap` (relative).
inline void expectDepthNearlySame(const Image<float>& cpu, const Image<float>& gl, double rel, double fraction,
                                  double cap) {
    int over = 0, covered = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < cpu.size() && k < gl.size(); ++k) {
        const double a = cpu.pixels[k], b = gl.pixels[k];
        if (!std::isfinite(a) || !std::isfinite(b)) continue;
        ++covered;
        const double d = std::abs(b - a) / std::abs(a);
        over += d > rel;
        worst = std::max(worst, d);
    }
    EXPECT_LE(over, int(fraction * covered) + 2) << "pixels beyond " << rel << " of " << covered;
    EXPECT_LE(worst, cap);
    std::printf("  depth: %d of %d pixels beyond %.0e, worst %.2g\n", over, covered, rel, worst);
}

// ---- Plain scalars (thickness) ----------------------------------------------
struct ScalarDiff {
    double maxAbs = 0.0;   // max |gl - cpu|
    double maxRel = 0.0;   // max |gl - cpu| / max(|cpu|, floor)
    int nonFinite = 0;     // NaN/inf on either side where the other is finite
};
inline ScalarDiff compareScalar(const Image<float>& cpu, const Image<float>& gl, double relFloor) {
    ScalarDiff d;
    EXPECT_EQ(cpu.size(), gl.size());
    for (std::size_t k = 0; k < cpu.size() && k < gl.size(); ++k) {
        const double a = cpu.pixels[k], b = gl.pixels[k];
        if (std::isfinite(a) != std::isfinite(b)) {
            ++d.nonFinite;
            continue;
        }
        if (!std::isfinite(a)) continue;
        d.maxAbs = std::max(d.maxAbs, std::abs(b - a));
        d.maxRel = std::max(d.maxRel, std::abs(b - a) / std::max(std::abs(a), relFloor));
    }
    return d;
}

// ---- Normals: angle in degrees over the pixels where `depth` has fluid -------
struct NormalDiff {
    double maxDeg = 0.0, meanDeg = 0.0, p99Deg = 0.0;
    int compared = 0;
};
inline NormalDiff compareNormals(const Image<glm::vec3>& cpu, const Image<glm::vec3>& gl, const Image<float>& depth) {
    NormalDiff d;
    EXPECT_EQ(cpu.size(), gl.size());
    std::vector<double> angles;
    for (std::size_t k = 0; k < cpu.size() && k < gl.size() && k < depth.size(); ++k) {
        if (!std::isfinite(depth.pixels[k])) continue;
        const glm::vec3 a = cpu.pixels[k], b = gl.pixels[k];
        const double la = glm::length(a), lb = glm::length(b);
        double deg = 180.0;
        if (la > 0 && lb > 0)
            deg = std::acos(std::clamp(double(glm::dot(a, b)) / (la * lb), -1.0, 1.0)) * 180.0 / 3.14159265358979;
        angles.push_back(deg);
    }
    d.compared = int(angles.size());
    if (angles.empty()) return d;
    double sum = 0.0;
    for (double a : angles) sum += a;
    d.meanDeg = sum / double(angles.size());
    std::sort(angles.begin(), angles.end());
    d.maxDeg = angles.back();
    d.p99Deg = angles[std::size_t(0.99 * double(angles.size() - 1))];
    return d;
}

// ---- Colour in 8-bit sRGB steps (what a PNG shows) --------------------------
inline int srgb8(float linear) {
    const double x = std::clamp(double(linear), 0.0, 1.0);
    const double v = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return int(std::lround(v * 255.0));
}
struct ColorDiff {
    int maxSteps = 0;          // largest |gl - cpu| of any channel in 8-bit sRGB steps (alpha linear x 255)
    double fractionOver1 = 0;  // fraction of pixels with any channel off by more than one step
};
inline ColorDiff compareColor(const Image<glm::vec4>& cpu, const Image<glm::vec4>& gl) {
    ColorDiff d;
    EXPECT_EQ(cpu.size(), gl.size());
    std::size_t over = 0;
    for (std::size_t k = 0; k < cpu.size() && k < gl.size(); ++k) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(srgb8(cpu.pixels[k][c]) - srgb8(gl.pixels[k][c])));
        worst = std::max(worst, int(std::lround(std::abs(cpu.pixels[k].a - gl.pixels[k].a) * 255.0)));
        d.maxSteps = std::max(d.maxSteps, worst);
        over += worst > 1;
    }
    d.fractionOver1 = cpu.empty() ? 0.0 : double(over) / double(cpu.size());
    return d;
}

// The whole-pipeline colour tolerance (gl_backend_test's): at most 2 sRGB
// steps anywhere and 0.1% of the pixels off by more than 1. Returns the diff
// for the caller's log line.
inline ColorDiff expectPipelineColor(const Image<glm::vec4>& cpu, const Image<glm::vec4>& gl, const std::string& what) {
    const ColorDiff c = compareColor(cpu, gl);
    EXPECT_LE(c.maxSteps, 2) << what;
    EXPECT_LE(c.fractionOver1, 1e-3) << what;
    return c;
}

// The time of stage `name` among a render's stage times; -1 when it did not run.
inline double stageMs(const std::vector<StageTime>& times, const std::string& name) {
    for (const StageTime& t : times)
        if (t.stage == name) return t.ms;
    return -1.0;
}

// The real frame with its attributes (velocities, ids; realFrame() keeps the positions only).
inline const ParticleSet& realSet() {
    static const ParticleSet set = [] {
        auto s = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
        EXPECT_TRUE(s.ok()) << s.error().describe();
        return s ? std::move(*s) : ParticleSet{};
    }();
    return set;
}

// The real frame's settings at w x h pixels: its estimated radius and its
// auto-framed camera (what the whole-pipeline parity tests start from).
inline RenderSettings realFrameSettings(int w, int h) {
    RenderSettings s;
    s.radiusM = realFrame().radius;
    s.camera = realFrameCamera(w, h);
    return s;
}

// One frame on the CPU reference and on GL, with their stage times.
struct BackendFrames {
    Aovs cpu, gl;
    std::vector<StageTime> cpuTimes, glTimes;
};
// Renders `view` with `s` on both; false (the test failed, with the error)
// when either render fails.
inline bool renderOnBoth(Renderer& cpu, Renderer& gl, const ParticleView& view, const RenderSettings& s,
                         BackendFrames& out) {
    auto a = cpu.render(view, s, &out.cpuTimes);
    auto b = gl.render(view, s, &out.glTimes);
    EXPECT_TRUE(a.ok()) << (a ? std::string() : a.error().describe());
    EXPECT_TRUE(b.ok()) << (b ? std::string() : b.error().describe());
    if (!a || !b) return false;
    out.cpu = std::move(*a);
    out.gl = std::move(*b);
    return true;
}

}  // namespace meniscus::test
