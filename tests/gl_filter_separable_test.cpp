// GL separable smoothing filters (docs/pipeline.md#smoothing,
// src/gl/filter_separable.cpp) and the thickness blur
// (docs/pipeline.md#thickness) against the CPU references cpu::filterGaussian /
// filterBilateral / filterBinomial and the blur of cpu::splatDepthAndThickness:
// synthetic scenes, the real SPlisHSPlasH frame, separate bodies, no-fluid
// images and fluid touching the image border. Skips only when no headless GL
// 4.3 context can be created at all.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/resource.h>

#include "cpu/filters.h"
#include "cpu/splat.h"
#include "cpu/thickness.h"
#include "gl/filter_separable.h"
#include "gl/uniforms.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "gl_test_util.h"
#include "test_util.h"

namespace gl_filter_separable_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kR = 0.01f;  // particle radius of the synthetic scenes, metres

// Tolerances, shared by every filter case:
//  - depth: relative 1e-6 (about 8 float ulps) where both have fluid. The
//    shaders run the CPU's operations in the CPU's order on the CPU's own
//    weight tables (`precise`, no FMA), so on llvmpipe the result is
//    bit-identical (measured max rel 0 in every case below); the margin is for
//    drivers whose division (s = k / z0, sumD / sumW) is not correctly rounded.
//  - coverage: +inf stays +inf and finite stays finite on both sides: no pixel
//    may differ.
constexpr double kDepthRel = 1e-6;
// Thickness blur: relative 1e-6 of max(|cpu|, 1 mm). Same sums in the same
// order on the same table (bit-identical on llvmpipe: measured 0); the margin
// is for a division kPxDepth / z or the border renormalisation rounded
// differently. (A flip of the whole-pixel radius ceil(3 sigma_px) would be a
// ~1e-2 change and fails the test.)
constexpr double kThicknessRel = 1e-6;
constexpr double kThicknessFloorM = 1e-3;

FilterParams withKind(int kind) {
    switch (kind) {
        case 1: return GaussianParams{};
        case 2: return BilateralParams{};
        default: return BinomialParams{};
    }
}
const char* kindName(int kind) { return kind == 1 ? "gaussian" : kind == 2 ? "bilateral" : "binomial"; }

Image<float> cpuFilter(const Image<float>& depth, const Camera& cam, float r, const FilterParams& p) {
    return cpu::smoothDepth(depth, cam, r, p);
}

class GlSeparable : public GlTest {
protected:
    void SetUp() override {
        GlTest::SetUp();
        if (IsSkipped()) return;
        auto f = gl::SeparableFilters::create();
        ASSERT_TRUE(f.ok()) << f.error().describe();
        filters_ = std::make_unique<gl::SeparableFilters>(std::move(*f));
    }

    // GL twin of cpuFilter: uploads the frame block and the depth, runs, reads back.
    Image<float> glFilter(const Image<float>& depth, const Camera& cam, float r, const FilterParams& p) {
        block_.upload(gl::packFrameParams(cam, r, p, ThicknessParams{}, ShadingParams{}));
        gl::GpuImage in, out;
        in.upload(depth);
        filters_->run(gl::packFrameParams(cam, r, p, ThicknessParams{}, ShadingParams{}), *gl::separableKind(p), in, out);
        return out.download<float>();
    }

    Image<float> glBlurThickness(const Image<float>& rawDepth, const Image<float>& thickness, const Camera& cam,
                                 float r, const ThicknessParams& t) {
        const auto frame = gl::packFrameParams(cam, r, NoFilter{}, t, ShadingParams{});
        block_.upload(frame);
        gl::GpuImage depth, thick;
        depth.upload(rawDepth);
        thick.upload(thickness);
        filters_->blurThickness(frame, depth, thick);
        return thick.download<float>();
    }

    // GL vs CPU for one filter; returns the difference (and checks it).
    DepthDiff expectFilterMatches(const Image<float>& depth, const Camera& cam, float r, const FilterParams& p,
                                  const std::string& what) {
        const Image<float> cpu = cpuFilter(depth, cam, r, p);
        const Image<float> gl = glFilter(depth, cam, r, p);
        const DepthDiff d = compareDepth(cpu, gl);
        std::printf("%-28s %-9s covered %7d, coverage diffs %d, max rel %.3g, mean rel %.3g\n", what.c_str(),
                    kindName(int(p.index())), d.coveredCpu, d.coverageDiffer, d.maxRel, d.meanRel);
        EXPECT_EQ(d.coverageDiffer, 0) << what << " " << kindName(int(p.index()));
        EXPECT_LE(d.maxRel, kDepthRel) << what << " " << kindName(int(p.index()));
        // The filter must actually have changed something (else the comparison proves little).
        int changed = 0;
        for (std::size_t k = 0; k < depth.size(); ++k) changed += std::isfinite(depth.pixels[k]) && cpu.pixels[k] != depth.pixels[k];
        EXPECT_GT(changed, d.coveredCpu / 2) << what;
        return d;
    }

    gl::FrameParamsBlock block_;
    std::unique_ptr<gl::SeparableFilters> filters_;
};

// 40x40x4 particles at spacing 2r, jitter 0.1 spacing, two interleaved grids
// (as tests/filter_separable_test.cpp), seen face-on from 1.2 m: projected
// radius ~4 px, kernel radii ~24 px.
struct FlatBlock {
    Camera camera = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.2f, 480, 360);
    Image<float> depth;
    explicit FlatBlock(float distance = 1.2f) {
        camera = faceOnCamera({0.0f, 0.0f, 0.0f}, distance, 480, 360);
        const float s = 2.0f * kR;
        auto pts = jitteredBlock({40, 40, 2}, s, 0.1f, {-19.5f * s, -19.5f * s, -1.0f * s}, 1);
        const auto odd = jitteredBlock({40, 40, 2}, s, 0.1f, {-19.0f * s, -19.0f * s, -1.5f * s}, 2);
        pts.insert(pts.end(), odd.begin(), odd.end());
        depth = cpu::splatDepth(camera, pts, kR);
    }
};

// The shared real frame (gl_test_util.h) splatted at w x h.
struct SplattedRealFrame {
    const std::vector<glm::vec3>& positions = realFrame().positions;
    float r = realFrame().radius;
    Camera camera;
    Image<float> depth;
    SplattedRealFrame(int w, int h) : camera(realFrameCamera(w, h)) {
        if (!positions.empty()) depth = cpu::splatDepth(camera, positions, r);
    }
};

}  // namespace

TEST_F(GlSeparable, FlatBlockMatchesCpu) {
    const FlatBlock b;
    for (int kind = 1; kind <= 3; ++kind) expectFilterMatches(b.depth, b.camera, kR, withKind(kind), "flat block");
}

TEST_F(GlSeparable, BallMatchesCpu) {
    // A sphere of fluid: sloped depth everywhere, so the blended (non-integer)
    // kernel radii and the bilateral range weights all vary across the image.
    const auto pos = shellBall({0.0f, 0.0f, 0.0f}, 0.25f, 2.0f * kR);
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.3f, 400, 300);
    const Image<float> depth = cpu::splatDepth(cam, pos, kR);
    for (int kind = 1; kind <= 3; ++kind) expectFilterMatches(depth, cam, kR, withKind(kind), "shell ball");
}

TEST_F(GlSeparable, RealFrameMatchesCpu) {
    const SplattedRealFrame f(320, 180);
    ASSERT_FALSE(f.depth.empty());
    for (int kind = 1; kind <= 3; ++kind) expectFilterMatches(f.depth, f.camera, f.r, withKind(kind), "real frame");
}

TEST_F(GlSeparable, OddParametersMatchCpu) {
    // Non-default parameters: a small kernel cap (every kernel clipped at the
    // cap), one and three iterations, a tight jump and a narrow range sigma.
    const FlatBlock b(0.6f);  // closer: kernels of ~48 px, capped
    GaussianParams g;
    g.maxKernelPx = 7;
    g.iterations = 3;
    expectFilterMatches(b.depth, b.camera, kR, g, "flat block, cap 7, 3 it");
    BilateralParams bl;
    bl.rangeSigmaRadii = 0.5f;
    bl.jumpRadii = 2.0f;
    bl.iterations = 1;
    expectFilterMatches(b.depth, b.camera, kR, bl, "flat block, range 0.5 r");
    BinomialParams bn;
    bn.sizeRadii = 1.3f;
    bn.maxKernelPx = 64;
    expectFilterMatches(b.depth, b.camera, kR, bn, "flat block, size 1.3 r");
}

TEST_F(GlSeparable, FluidTouchingTheBorderMatchesCpu) {
    // The block fills the whole image: every kernel near the border loses its
    // off-image taps and is renormalised; rows and columns of +inf cut in.
    FlatBlock b(0.35f);
    for (int y = 0; y < b.depth.height; ++y) b.depth.at(b.depth.width / 2, y) = kInf;  // a +inf column
    for (int x = 0; x < b.depth.width; ++x) b.depth.at(x, 5) = kInf;                    // a +inf row
    b.depth.at(10, 10) = std::numeric_limits<float>::quiet_NaN();                        // NaN: no fluid too
    int finite = 0;
    for (int x = 0; x < b.depth.width; ++x) finite += std::isfinite(b.depth.at(x, 0));
    ASSERT_GT(finite, b.depth.width / 2);  // the top row really holds fluid
    for (int kind = 1; kind <= 3; ++kind) expectFilterMatches(b.depth, b.camera, kR, withKind(kind), "border");
    const Image<float> gl = glFilter(b.depth, b.camera, kR, GaussianParams{});
    EXPECT_TRUE(std::isinf(gl.at(10, 10)));
    EXPECT_TRUE(std::isinf(gl.at(b.depth.width / 2, 100)));
}

namespace {
// How far smoothing pulled each body toward the other: the mean |change| of
// the pixels of one body within 8 px (along the row) of a pixel of the other,
// the larger of the two bodies, in metres; and whether every pixel stayed on
// its side of zMid (between the bodies).
struct Separation {
    double meanShiftM = 0.0;
    bool sidesKept = true;
};
Separation separation(const Image<float>& raw, const Image<float>& smoothed, float zMid) {
    Separation out;
    double sum[2] = {0, 0};
    int count[2] = {0, 0};
    for (int y = 0; y < raw.height; ++y)
        for (int x = 0; x < raw.width; ++x) {
            const float z = raw.at(x, y);
            if (!std::isfinite(z)) continue;
            const int side = z < zMid ? 0 : 1;
            if ((smoothed.at(x, y) < zMid ? 0 : 1) != side) out.sidesKept = false;
            bool nearOther = false;
            for (int dx = -8; dx <= 8 && !nearOther; ++dx) {
                const int xx = x + dx;
                if (xx < 0 || xx >= raw.width || !std::isfinite(raw.at(xx, y))) continue;
                nearOther = (raw.at(xx, y) < zMid ? 0 : 1) != side;
            }
            if (!nearOther) continue;
            sum[side] += std::abs(double(smoothed.at(x, y)) - double(z));
            ++count[side];
        }
    EXPECT_GT(count[0], 100);
    EXPECT_GT(count[1], 100);
    for (int b = 0; b < 2; ++b)
        if (count[b]) out.meanShiftM = std::max(out.meanShiftM, sum[b] / count[b]);
    return out;
}
}  // namespace

TEST_F(GlSeparable, SeparateBodiesStaySeparate) {
    // Two thin blocks whose front faces are 10 r apart in depth, overlapping on
    // screen: the near one (eye depth ~1.19 m) hides part of the far one
    // (~1.29 m), so the two meet along a vertical edge in the image.
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.2f, 480, 360);
    const float s = 2.0f * kR;
    auto pts = jitteredBlock({20, 20, 2}, s, 0.1f, {-0.3f, -0.2f, -s}, 1);
    const auto back = jitteredBlock({20, 20, 2}, s, 0.1f, {-0.1f, -0.2f, -s - 10.0f * kR}, 2);
    pts.insert(pts.end(), back.begin(), back.end());
    const Image<float> depth = cpu::splatDepth(cam, pts, kR);
    const float zMid = 1.2f + 0.5f * 10.0f * kR - kR;  // halfway between the front faces
    const double kBlendShiftM = 2.0 * kR;
    for (int kind = 1; kind <= 3; ++kind) {
        expectFilterMatches(depth, cam, kR, withKind(kind), "two bodies");
        const Separation sep = separation(depth, glFilter(depth, cam, kR, withKind(kind)), zMid);
        std::printf("  %s: mean shift next to the other body %.3g r\n", kindName(kind), sep.meanShiftM / kR);
        // Next to the other body a pixel moves like any other (smoothing the
        // sphere bumps: measured ~0.5 r); a blend across the 10 r gap moves it
        // by several r (the control below: ~6.5 r).
        EXPECT_TRUE(sep.sidesKept) << kindName(kind);
        EXPECT_LT(sep.meanShiftM, kBlendShiftM) << kindName(kind);
    }
    // Control: with the jump test effectively off the same measure does see
    // the blend (so the check above can fail).
    GaussianParams blind;
    blind.jumpRadii = 1000.0f;
    const Separation sep = separation(depth, glFilter(depth, cam, kR, blind), zMid);
    std::printf("  gaussian without the jump test: mean shift %.3g r\n", sep.meanShiftM / kR);
    EXPECT_GT(sep.meanShiftM, kBlendShiftM);
}

TEST_F(GlSeparable, NoFluidStaysInfinite) {
    const Camera cam = faceOnCamera({0.0f, 0.0f, 0.0f}, 1.0f, 67, 45);  // not a multiple of the work group
    const Image<float> depth(cam.width, cam.height, kInf);
    for (int kind = 1; kind <= 3; ++kind) {
        const Image<float> gl = glFilter(depth, cam, kR, withKind(kind));
        ASSERT_EQ(gl.size(), depth.size());
        for (float z : gl.pixels) ASSERT_TRUE(std::isinf(z) && z > 0) << kindName(kind);
    }
}

TEST_F(GlSeparable, NoFilterOrZeroIterationsCopies) {
    const FlatBlock b;
    GaussianParams g;
    g.iterations = 0;
    for (const FilterParams& p : {FilterParams{NoFilter{}}, FilterParams{g}, FilterParams{CurvatureFlowParams{}}}) {
        const Image<float> gl = glFilter(b.depth, b.camera, kR, p);
        ASSERT_EQ(gl.size(), b.depth.size());
        for (std::size_t k = 0; k < gl.size(); ++k)
            ASSERT_TRUE(gl.pixels[k] == b.depth.pixels[k] || (std::isinf(gl.pixels[k]) && std::isinf(b.depth.pixels[k])));
    }
}

namespace {
ScalarDiff expectThicknessMatches(const Image<float>& cpu, const Image<float>& gl, const Image<float>& unblurred,
                                  const Image<float>& rawDepth, const char* what) {
    const ScalarDiff d = compareScalar(cpu, gl, kThicknessFloorM);
    std::printf("thickness %-22s max abs %.3g m, max rel %.3g\n", what, d.maxAbs, d.maxRel);
    EXPECT_EQ(d.nonFinite, 0) << what;
    EXPECT_LE(d.maxRel, kThicknessRel) << what;
    // Pixels without fluid keep their value exactly; the blur changed the others.
    int changed = 0, fluid = 0;
    for (std::size_t k = 0; k < gl.size(); ++k) {
        if (!std::isfinite(rawDepth.pixels[k])) {
            EXPECT_EQ(gl.pixels[k], unblurred.pixels[k]) << what << " pixel " << k;
            continue;
        }
        ++fluid;
        changed += gl.pixels[k] != unblurred.pixels[k];
    }
    EXPECT_GT(changed, fluid / 2) << what;
    return d;
}
}  // namespace

TEST_F(GlSeparable, ThicknessBlurRealFrameMatchesCpu) {
    const SplattedRealFrame f(320, 180);
    ASSERT_FALSE(f.depth.empty());
    ThicknessParams raw;
    raw.blurSigmaRadii = 0.0f;
    const cpu::DepthAndThickness unblurred = cpu::splatDepthAndThickness(f.camera, f.positions, f.r, raw);
    for (float sigma : {1.0f, 3.0f}) {
        ThicknessParams t;
        t.blurSigmaRadii = sigma;
        const cpu::DepthAndThickness cpu = cpu::splatDepthAndThickness(f.camera, f.positions, f.r, t);
        const Image<float> gl = glBlurThickness(unblurred.depth, unblurred.thickness, f.camera, f.r, t);
        expectThicknessMatches(cpu.thickness, gl, unblurred.thickness, unblurred.depth,
                               sigma == 1.0f ? "real frame, sigma 1 r" : "real frame, sigma 3 r");
    }
}

TEST_F(GlSeparable, ThicknessBlurCappedAndBorderMatchesCpu) {
    // Fluid over the whole image (every border kernel renormalised) and a
    // kernel cap of 5 px that clips every kernel.
    const FlatBlock b(0.35f);
    const float s = 2.0f * kR;
    auto pts = jitteredBlock({40, 40, 2}, s, 0.1f, {-19.5f * s, -19.5f * s, -1.0f * s}, 1);
    ThicknessParams raw;
    raw.blurSigmaRadii = 0.0f;
    const cpu::DepthAndThickness unblurred = cpu::splatDepthAndThickness(b.camera, pts, kR, raw);
    ThicknessParams t;
    t.maxKernelPx = 5;
    const cpu::DepthAndThickness cpu = cpu::splatDepthAndThickness(b.camera, pts, kR, t);
    const Image<float> gl = glBlurThickness(unblurred.depth, unblurred.thickness, b.camera, kR, t);
    expectThicknessMatches(cpu.thickness, gl, unblurred.thickness, unblurred.depth, "border, cap 5 px");
}

TEST_F(GlSeparable, ThicknessBlurZeroSigmaIsNoOp) {
    const SplattedRealFrame f(160, 90);
    ASSERT_FALSE(f.depth.empty());
    ThicknessParams raw;
    raw.blurSigmaRadii = 0.0f;
    const cpu::DepthAndThickness unblurred = cpu::splatDepthAndThickness(f.camera, f.positions, f.r, raw);
    const Image<float> gl = glBlurThickness(unblurred.depth, unblurred.thickness, f.camera, f.r, raw);
    EXPECT_EQ(gl.pixels, unblurred.thickness.pixels);
}
}  // namespace gl_filter_separable_test_local
