// Hole filling (docs/pipeline.md#hole-filling, src/cpu/hole_fill.cpp,
// src/shared/hole_fill.h) and the thin-liquid thickness: holes closed in on
// every side are filled (planes stay planes), bays, gaps between drops, gaps
// between layers, gaps wider than the span and pixels behind the scene are not;
// the same bits for any thread count; and the case hole filling is for: a sheet
// one particle thick at rest spacing renders with full coverage and no pixel
// darker or greyer than its neighbours beyond the bounds below, which it breaks
// without the two.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "cpu/hole_fill.h"
#include "meniscus/renderer.h"
#include "shared/hole_fill.h"
#include "test_util.h"

namespace hole_fill_test_local {

using namespace meniscus;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A 64 x 64 camera whose focal length is 64 pixels (fov about 53 degrees):
// at depth 2 m a radius of 0.05 m is 1.6 pixels, and the default span of
// 4 r is 6.4 pixels.
Camera testCamera() {
    Camera c = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 64, 64, 2.0f * std::atan(0.5f) * 57.29577951f);
    return c;
}
constexpr float kR = 0.05f;

// A W x H depth of value z everywhere, with the rectangle [x0, x1) x [y0, y1) uncovered.
Image<float> plateWithHole(int W, int H, float z, int x0, int x1, int y0, int y1) {
    Image<float> d(W, H, z);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) d.at(x, y) = kInf;
    return d;
}

}  // namespace

TEST(HoleFill, TheCameraOfTheseTestsHasAFocalLengthOf64Pixels) {
    EXPECT_NEAR(testCamera().focalPx(), 64.0f, 1e-3f);
}

TEST(HoleFill, ASmallHoleInAPlateTakesThePlatesDepthAndItsThickness) {
    const Camera cam = testCamera();
    Image<float> d = plateWithHole(64, 64, 2.0f, 30, 33, 30, 33);
    Image<float> t(64, 64, 0.1f);
    for (int y = 30; y < 33; ++y)
        for (int x = 30; x < 33; ++x) t.at(x, y) = 0.02f;  // the blur's reach into the hole
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, d, t), 9u);
    for (int y = 30; y < 33; ++y)
        for (int x = 30; x < 33; ++x) {
            EXPECT_EQ(d.at(x, y), 2.0f) << x << "," << y;
            EXPECT_EQ(t.at(x, y), 0.1f) << x << "," << y;  // the larger: the lines' 0.1
        }
    // Off: nothing changes.
    Image<float> off = plateWithHole(64, 64, 2.0f, 30, 33, 30, 33), t2(64, 64, 0.1f);
    HoleFillParams p;
    p.enabled = false;
    EXPECT_EQ(cpu::fillHoles(cam, kR, p, nullptr, off, t2), 0u);
    EXPECT_EQ(off.at(31, 31), kInf);
}

TEST(HoleFill, PlanesStayPlanes) {
    // A tilted plane's depth z = a + b x + c y (linear in the pixels), holes
    // of one to four pixels: each filled pixel is the plane's own depth (every
    // line interpolates a linear function exactly, up to rounding).
    const Camera cam = testCamera();
    Image<float> d(64, 64);
    auto plane = [](int x, int y) { return 2.0f + 0.004f * float(x) - 0.003f * float(y); };
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) d.at(x, y) = plane(x, y);
    const int holes[][4] = {{10, 11, 10, 11}, {20, 22, 12, 14}, {40, 44, 40, 43}, {12, 15, 45, 46}};
    int n = 0;
    for (const auto& h : holes)
        for (int y = h[2]; y < h[3]; ++y)
            for (int x = h[0]; x < h[1]; ++x, ++n) d.at(x, y) = kInf;
    Image<float> t(64, 64, 0.0f);
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, d, t), std::size_t(n));
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) ASSERT_NEAR(d.at(x, y), plane(x, y), 2e-6f) << x << "," << y;
}

TEST(HoleFill, BaysGapsBetweenDropsAndGapsBetweenLayersStay) {
    const Camera cam = testCamera();
    Image<float> t;
    // A bay: a notch 3 wide cut into the plate's top edge, open above.
    Image<float> bay = plateWithHole(64, 64, 2.0f, 0, 64, 0, 20);
    for (int y = 20; y < 24; ++y)
        for (int x = 30; x < 33; ++x) bay.at(x, y) = kInf;
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, bay, t), 0u);
    // Two drops side by side (a gap closed along the row only).
    Image<float> drops(64, 64, kInf);
    for (int y = 28; y < 34; ++y)
        for (int x = 20; x < 26; ++x) drops.at(x, y) = drops.at(x + 8, y) = 2.0f;
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, drops, t), 0u);
    // A gap between a near layer (left) and a far one (right): 0.5 m apart,
    // far beyond the jump of 5 r = 0.25 m.
    Image<float> layers(64, 64, 2.0f);
    for (int y = 0; y < 64; ++y)
        for (int x = 32; x < 64; ++x) layers.at(x, y) = 2.5f;
    for (int y = 30; y < 33; ++y)
        for (int x = 31; x < 33; ++x) layers.at(x, y) = kInf;
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, layers, t), 0u);
}

TEST(HoleFill, TheWidestGapFilledIsTheSpanInRadii) {
    // At depth 2 with f = 64 px and r = 0.05 m the span of 4 r is 6.4 pixels.
    // A square hole of 3 pixels (lines of 4 steps, diagonals 4 sqrt 2 = 5.7)
    // is filled; of 7 pixels (rows and columns of 8 steps) it is not; a span
    // of 9 r (14.4 pixels: diagonals of 8 sqrt 2 = 11.3) fills it.
    const Camera cam = testCamera();
    Image<float> t;
    Image<float> three = plateWithHole(64, 64, 2.0f, 30, 33, 30, 33);
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, three, t), 9u);
    Image<float> seven = plateWithHole(64, 64, 2.0f, 28, 35, 28, 35);
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, seven, t), 0u);
    HoleFillParams wide;
    wide.maxSpanRadii = 9.0f;
    EXPECT_EQ(cpu::fillHoles(cam, kR, wide, nullptr, seven, t), 49u);
    // The span is in the world: the same 3-pixel hole seen 3x farther is 3x
    // wider in radii (the plate at 6 m: 4 r is 2.1 pixels) and stays.
    Image<float> far = plateWithHole(64, 64, 6.0f, 30, 33, 30, 33);
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, far, t), 0u);
    // The formulas: a diagonal step counts sqrt 2; the depth jump.
    EXPECT_EQ(shared::holeLineLengthPx(3, 3, false), 6.0f);
    EXPECT_TRUE(shared::holeLineNarrow(2.0f, shared::holeLineLengthPx(3, 3, false), kR, 64.0f, 4.0f));
    EXPECT_FALSE(shared::holeLineNarrow(2.0f, shared::holeLineLengthPx(3, 3, true), kR, 64.0f, 4.0f));
    // One surface: 5 r = 0.25 m, plus a climb of 2 per metre across (a line
    // of 3.2 pixels at 2 m is 0.1 m across: 0.2 m more).
    EXPECT_TRUE(shared::holeLineSameSurface(2.0f, 2.44f, 2.0f, 3.2f, kR, 64.0f, 5.0f));
    EXPECT_FALSE(shared::holeLineSameSurface(2.0f, 2.46f, 2.0f, 3.2f, kR, 64.0f, 5.0f));
}

TEST(HoleFill, ASlitMayBeLongOneWayUpToTheReach) {
    // A slit one pixel tall between two bands of liquid (two rows of
    // particles seen at a slant): long along the row, narrow on the three
    // other lines; filled when its ends lie within the reach.
    const Camera cam = test::faceOnCamera(glm::vec3(0.0f), 2.0f, 160, 64, 2.0f * std::atan(0.5f) * 57.29577951f);
    Image<float> t;
    Image<float> slit = plateWithHole(160, 64, 2.0f, 40, 60, 31, 32);
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, slit, t), 20u);
    Image<float> longSlit = plateWithHole(160, 64, 2.0f, 10, 150, 31, 32);  // 140 pixels: past the reach of 64
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, nullptr, longSlit, t), 0u);
}

TEST(HoleFill, NeverInFrontOfTheScene) {
    const Camera cam = testCamera();
    Image<float> d = plateWithHole(64, 64, 2.0f, 30, 33, 30, 33), t;
    Image<float> scene(64, 64, kInf);
    scene.at(31, 31) = 1.5f;  // a thin pole in front of the water, seen through the hole
    EXPECT_EQ(cpu::fillHoles(cam, kR, HoleFillParams{}, &scene, d, t), 8u);
    EXPECT_EQ(d.at(31, 31), kInf);
    EXPECT_EQ(d.at(30, 30), 2.0f);
}

TEST(HoleFill, SameBitsForAnyThreadCount) {
    // The real frame's splat has holes (spheres of the bulk radius): the fill
    // sees the splat as it came, so the order of the rows cannot matter.
    auto set = readParticles(test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string());
    ASSERT_TRUE(set) << set.error().describe();
    RenderSettings s;
    s.radiusM = 0.02f;  // a little small: more holes to fill
    s.camera = test::lookAt({2.5f, 2.1f, 2.9f}, {0.43f, 0.45f, 0.0f}, 320, 180);
    s.holeFill.enabled = false;
    auto raw = Renderer().render(set->positions, s);
    ASSERT_TRUE(raw) << raw.error().describe();
    Image<float> d[2] = {raw->rawDepth, raw->rawDepth}, t[2] = {raw->thickness, raw->thickness};
    std::size_t n[2];
    for (int k = 0; k < 2; ++k) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, k == 0 ? 1 : 4);
        n[k] = cpu::fillHoles(s.camera, s.radiusM, HoleFillParams{}, nullptr, d[k], t[k]);
    }
    EXPECT_GT(n[0], 50u);
    EXPECT_EQ(n[0], n[1]);
    EXPECT_EQ(test::differingBits(d[0], d[1]), 0);
    EXPECT_EQ(test::differingBits(t[0], t[1]), 0);
}

TEST(ThinLiquid, TheThicknessIsAtLeastTheFloor) {
    EXPECT_EQ(shared::thinLiquidThickness(0.0f, 1.0f, 0.02f), 0.02f);
    EXPECT_EQ(shared::thinLiquidThickness(0.5f, 1.0f, 0.02f), 0.5f);
    EXPECT_EQ(shared::thinLiquidThickness(0.001f, 0.0f, 0.02f), 0.001f);
}

namespace {

// The sheet: one layer of particles at rest spacing 2 r in the plane
// z = 0 (a 40 x 30 square lattice, jittered by 15 % of the spacing in x and y
// as a simulation leaves it), seen face on and at 50 degrees, over the studio.
struct SheetStats {
    double coverage;        // fluid pixels / pixels inside the sheet's outline (2 r margin)
    double worstDarker;     // largest luminance drop below the 5 x 5 neighbourhood median
    double worstGreyer;     // largest chroma (max - min of linear RGB) drop below that median
};

SheetStats renderSheet(bool fixes, float tiltDegrees) {
    const float r = 0.01f, s = 2.0f * r;
    std::vector<glm::vec3> pts;
    for (int j = 0; j < 30; ++j)
        for (int i = 0; i < 40; ++i) {
            const std::uint32_t k = std::uint32_t(j * 40 + i);
            pts.emplace_back((float(i) + 0.15f * (2.0f * test::hash01(k, 1) - 1.0f)) * s,
                             (float(j) + 0.15f * (2.0f * test::hash01(k, 2) - 1.0f)) * s + 0.3f, 0.0f);
        }
    const glm::vec3 mid(19.5f * s, 14.5f * s + 0.3f, 0.0f);
    const float a = tiltDegrees * 3.14159265f / 180.0f, dist = 1.0f;
    RenderSettings rs;
    rs.radiusM = r;
    rs.scene.background = false;
    rs.camera = test::lookAt(mid + dist * glm::vec3(std::sin(a), 0.0f, std::cos(a)), mid, 240, 180);
    if (!fixes) {  // the spheres as they were: no anisotropic kernels, no filling, no floor
        rs.anisotropy.enabled = false;
        rs.holeFill.enabled = false;
        rs.thickness.minRadii = 0.0f;
    }
    auto out = Renderer().render(pts, rs);
    EXPECT_TRUE(out) << out.error().describe();
    SheetStats st{0.0, 0.0, 0.0};
    if (!out) return st;
    // The sheet's outline shrunk by two spacings (a gap between two particles
    // of the edge row is a bay, open to the outside), projected: the pixels
    // that must be liquid.
    const Camera& cam = rs.camera;
    const int W = cam.width, H = cam.height;
    auto inside = [&](int x, int y) {
        const glm::vec3 lo(2.0f * s, 0.3f + 2.0f * s, 0.0f);
        const glm::vec3 hi(37.0f * s, 27.0f * s + 0.3f, 0.0f);
        // Intersect the pixel's ray with z = 0.
        const glm::vec3 o = cam.eye;
        const float f = cam.focalPx();
        const glm::vec3 d = cam.right() * ((float(x) + 0.5f - 0.5f * float(W)) / f) +
                            cam.trueUp() * (-(float(y) + 0.5f - 0.5f * float(H)) / f) - cam.back();
        if (std::abs(d.z) < 1e-6f) return false;
        const float tt = -o.z / d.z;
        const glm::vec3 p = o + tt * d;
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
    };
    auto lum = [](const glm::vec4& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
    auto chroma = [](const glm::vec4& c) { return double(std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b})); };
    int in = 0, covered = 0;

    for (int y = 2; y < H - 2; ++y)
        for (int x = 2; x < W - 2; ++x) {
            if (!inside(x, y)) continue;
            ++in;
            if (out->depth.at(x, y) < kInf) ++covered;
            std::vector<double> ls, cs;
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) {
                    ls.push_back(lum(out->color.at(x + dx, y + dy)));
                    cs.push_back(chroma(out->color.at(x + dx, y + dy)));
                }
            std::nth_element(ls.begin(), ls.begin() + 12, ls.end());
            std::nth_element(cs.begin(), cs.begin() + 12, cs.end());
            const glm::vec4 c = out->color.at(x, y);
            st.worstDarker = std::max(st.worstDarker, ls[12] - lum(c));
            st.worstGreyer = std::max(st.worstGreyer, cs[12] - chroma(c));
        }
    st.coverage = in ? double(covered) / double(in) : 0.0;
    EXPECT_GT(in, 2000);
    return st;
}

}  // namespace

TEST(ThinSheet, OneParticleThickRendersWholeAndEvenlyTinted) {
    // Bounds: every pixel inside the outline is liquid; none is more than
    // 0.03 darker (linear luminance) than its 5 x 5 neighbourhood's median,
    // nor 0.06 less tinted (chroma, linear). Measured: 0.009 and 0.03 face
    // on, 0.005 and 0.02 at 50 degrees. Over the sky (no studio: its checker
    // edges would be steps of their own).
    for (float tilt : {0.0f, 50.0f}) {
        const SheetStats with = renderSheet(true, tilt);
        EXPECT_EQ(with.coverage, 1.0) << "tilt " << tilt;
        EXPECT_LT(with.worstDarker, 0.03) << "tilt " << tilt;
        EXPECT_LT(with.worstGreyer, 0.06) << "tilt " << tilt;
        // As spheres, without the hole filling and the thin-liquid floor, the same sheet
        // has holes (10-23 % of the pixels), drawn as the background: the
        // test can fail.
        const SheetStats without = renderSheet(false, tilt);
        EXPECT_LT(without.coverage, 0.95) << "tilt " << tilt;
        EXPECT_GT(without.worstDarker, 0.3) << "tilt " << tilt;
    }
}
}  // namespace hole_fill_test_local
