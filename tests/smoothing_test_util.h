// Scenes and surface measures shared by the smoothing-filter tests
// (docs/pipeline.md#smoothing): splatted particle blocks seen face-on, normals
// by back-projection, roughness.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "cpu/splat.h"
#include "meniscus/camera.h"
#include "meniscus/types.h"
#include "test_util.h"

namespace meniscus::test {

// A jittered block of particles (40×40×4, spacing 2r, jitter 0.1·spacing) whose
// front layer of centres lies on world z = 0, centred on x = y = 0, seen face-on
// from 1.4 m at 400×400 (projected radius ≈ 4 px). Everything scales with `s`.
struct SmoothingScene {
    Camera camera;
    float radius = 0.0f;
    std::vector<glm::vec3> positions;
    Image<float> depth;
    float faceDepth = 0.0f;  // eye depth of the block's nominal front surface (centre z + r)
};

// Odd layers of a jittered block shifted by half a spacing in x and y, so that
// seen face-on the next layer covers the diamond-shaped holes a square lattice
// of touching spheres leaves (21% of the face). Aligned layers would show
// through-holes to +inf that no filter may fill.
inline std::vector<glm::vec3> staggeredBlock(glm::ivec3 n, float spacing, glm::vec3 origin, unsigned seed = 1) {
    auto pts = jitteredBlock(n, spacing, 0.1f, origin, seed);
    const std::size_t layer = std::size_t(n.x) * std::size_t(n.y);
    for (std::size_t i = 0; i < pts.size(); ++i)
        if ((i / layer) % 2 == 1) pts[i] += glm::vec3(0.5f * spacing, 0.5f * spacing, 0.0f);
    return pts;
}

inline SmoothingScene blockScene(float s = 1.0f) {
    SmoothingScene sc;
    sc.radius = 0.01f * s;
    const float spacing = 2.0f * sc.radius;
    // Front layer (k = 3, odd: shifted) centred on x = y = 0.
    sc.positions = staggeredBlock({40, 40, 4}, spacing, s * glm::vec3(-0.40f, -0.40f, -0.06f));
    sc.camera = faceOnCamera(glm::vec3(0.0f), 1.4f * s, 400, 400);
    sc.depth = cpu::splatDepth(sc.camera, sc.positions, sc.radius);
    sc.faceDepth = 1.4f * s - sc.radius;
    return sc;
}

// View-space unit normal at pixel (x, y) from back-projected central
// differences (+z toward the camera); false when a neighbour is missing or more
// than `jump` metres away in depth.
inline bool pixelNormal(const Image<float>& d, const Camera& cam, int x, int y, float jump, glm::vec3* n) {
    if (x < 1 || y < 1 || x + 1 >= d.width || y + 1 >= d.height) return false;
    const float z = d.at(x, y);
    const float zl = d.at(x - 1, y), zr = d.at(x + 1, y), zu = d.at(x, y - 1), zd = d.at(x, y + 1);
    for (float q : {z, zl, zr, zu, zd})
        if (!std::isfinite(q) || std::fabs(q - z) > jump) return false;
    auto P = [&](int i, int j, float depth) { return cam.unproject(float(i) + 0.5f, float(j) + 0.5f, depth); };
    const glm::vec3 dx = P(x + 1, y, zr) - P(x - 1, y, zl);
    const glm::vec3 dy = P(x, y - 1, zu) - P(x, y + 1, zd);  // row 0 is the top: up is -row
    *n = glm::normalize(glm::cross(dx, dy));
    return true;
}

struct AngleStats {
    double meanDeg = 0.0, p95Deg = 0.0, maxDeg = 0.0;  // mean, 95th percentile, max
    int count = 0;
};

// Angles between the depth image's normals and `reference(viewPoint)` over the
// pixels whose back-projected view-space point passes `inside`.
inline AngleStats normalAngles(const Image<float>& d, const Camera& cam, float jump,
                               const std::function<bool(const glm::vec3&)>& inside,
                               const std::function<glm::vec3(const glm::vec3&)>& reference) {
    AngleStats st;
    std::vector<double> all;
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x) {
            if (!std::isfinite(d.at(x, y))) continue;
            const glm::vec3 p = cam.unproject(float(x) + 0.5f, float(y) + 0.5f, d.at(x, y));
            if (!inside(p)) continue;
            glm::vec3 n;
            if (!pixelNormal(d, cam, x, y, jump, &n)) continue;
            const double c = std::clamp(double(glm::dot(n, reference(p))), -1.0, 1.0);
            const double a = std::acos(c) * 180.0 / M_PI;
            all.push_back(a);
        }
    st.count = int(all.size());
    if (all.empty()) return st;
    std::sort(all.begin(), all.end());
    double sum = 0.0;
    for (double a : all) sum += a;
    st.meanDeg = sum / double(all.size());
    st.p95Deg = all[all.size() * 95 / 100];
    st.maxDeg = all.back();
    return st;
}

// Normal angles to the face normal (+z view) over the central half of the
// block's front face (|x|, |y| < 0.2 s in view space, away from its edges).
inline AngleStats blockFaceAngles(const Image<float>& d, const SmoothingScene& sc) {
    const float half = 0.2f * sc.radius / 0.01f;
    return normalAngles(
        d, sc.camera, 2.0f * sc.radius,
        [&](const glm::vec3& p) { return std::fabs(p.x) < half && std::fabs(p.y) < half; },
        [](const glm::vec3&) { return glm::vec3(0.0f, 0.0f, 1.0f); });
}

// Roughness of the block's central face: mean |4-neighbour Laplacian| of the
// depth in radii, over pixels whose neighbours are all within 2 r. Unlike
// central-difference normals it sees the pixel-checkerboard mode.
inline double blockFaceRoughness(const Image<float>& d, const SmoothingScene& sc) {
    const float half = 0.2f * sc.radius / 0.01f, r = sc.radius;
    double sum = 0.0;
    int n = 0;
    for (int y = 1; y + 1 < d.height; ++y)
        for (int x = 1; x + 1 < d.width; ++x) {
            const float z = d.at(x, y);
            if (!std::isfinite(z)) continue;
            const glm::vec3 p = sc.camera.unproject(float(x) + 0.5f, float(y) + 0.5f, z);
            if (std::fabs(p.x) >= half || std::fabs(p.y) >= half) continue;
            const float q[4] = {d.at(x - 1, y), d.at(x + 1, y), d.at(x, y - 1), d.at(x, y + 1)};
            bool ok = true;
            for (float v : q) ok = ok && std::fabs(v - z) <= 2.0f * r;
            if (!ok) continue;
            sum += std::fabs(double(q[0]) + q[1] + q[2] + q[3] - 4.0 * z) / r;
            ++n;
        }
    return n ? sum / n : 0.0;
}

// Eye depth of a tilted analytic plane through view point (0, 0, -z0) with view
// normal n, for every pixel (the exact ray-plane intersection).
inline Image<float> planeDepth(const Camera& cam, float z0, glm::vec3 n) {
    Image<float> d(cam.width, cam.height);
    n = glm::normalize(n);
    const float c = glm::dot(n, glm::vec3(0.0f, 0.0f, -z0));
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x)
            d.at(x, y) = c / glm::dot(n, cam.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
    return d;
}

// Two bodies overlapping on screen: the block of blockScene() and, in front of
// it, a 20×20×4 block whose back layer of spheres leaves a gap of 10 r to the
// far block's front spheres. nearFaceDepth is its nominal front surface.
struct TwoBodyScene {
    SmoothingScene far;       // the far block alone (its depth: far.depth)
    Image<float> nearDepth;   // the near block alone
    Image<float> depth;       // both
    float nearFaceDepth = 0.0f;
};

inline TwoBodyScene twoBodyScene() {
    TwoBodyScene t;
    t.far = blockScene();
    const float r = t.far.radius, spacing = 2.0f * r;
    // Far front centres at z = 0 (surface r); near back centres at 2r + 10r.
    const float nearBackZ = 12.0f * r;
    auto nearBlock = staggeredBlock({20, 20, 4}, spacing, glm::vec3(-0.20f, -0.20f, nearBackZ), 7);
    std::vector<glm::vec3> all = t.far.positions;
    all.insert(all.end(), nearBlock.begin(), nearBlock.end());
    t.depth = cpu::splatDepth(t.far.camera, all, r);
    t.nearDepth = cpu::splatDepth(t.far.camera, nearBlock, r);
    t.nearFaceDepth = 1.4f - (nearBackZ + 3.0f * spacing + r);
    return t;
}

// Bleeding between the two bodies, from a filter run on both bodies together
// and on each alone. Over pixels within 3 px of the other body:
//  nearMaxDiff: max |both − near alone| of near-body pixels, radii;
//  farMaxPull: max (far alone − both) of far-body pixels, radii, i.e. how far
//  the near body pulled a far pixel toward itself.
struct BleedStats {
    double nearMaxDiff = 0.0, farMaxPull = 0.0;
    int nNear = 0, nFar = 0;
};

inline BleedStats bleedStats(const TwoBodyScene& t, const std::function<Image<float>(const Image<float>&)>& filter) {
    const Image<float> both = filter(t.depth), nearAlone = filter(t.nearDepth), farAlone = filter(t.far.depth);
    const float r = t.far.radius, mid = 0.5f * (t.nearFaceDepth + t.far.faceDepth);
    const Image<float>& d = t.depth;
    BleedStats st;
    for (int y = 3; y + 3 < d.height; ++y)
        for (int x = 3; x + 3 < d.width; ++x) {
            const float z = d.at(x, y);
            if (!std::isfinite(z)) continue;
            const bool isNear = z < mid;
            bool touches = false;
            for (int j = -3; j <= 3; ++j)
                for (int i = -3; i <= 3; ++i) {
                    const float q = d.at(x + i, y + j);
                    touches = touches || (std::isfinite(q) && (q < mid) != isNear);
                }
            if (!touches) continue;
            if (isNear) {
                st.nearMaxDiff = std::max(st.nearMaxDiff, std::fabs(double(both.at(x, y)) - nearAlone.at(x, y)) / r);
                ++st.nNear;
            } else {
                st.farMaxPull = std::max(st.farMaxPull, (double(farAlone.at(x, y)) - both.at(x, y)) / r);
                ++st.nFar;
            }
        }
    return st;
}

// The two-body bleed bounds every smoothing test uses (faces 18 r apart, a
// bleed would be ~9 r): near-body pixels as with the near body alone within
// 0.01 r, far-body pixels pulled toward the near body by at most 1.25 r; both
// bands must hold over 1000 pixels. `who` prefixes the printed line.
inline void expectNoBleed(const BleedStats& st, const char* who) {
    std::printf("%s: near band %d px max diff %.3f r, far band %d px max pull %.3f r\n", who, st.nNear,
                st.nearMaxDiff, st.nFar, st.farMaxPull);
    ASSERT_GT(st.nNear, 1000);
    ASSERT_GT(st.nFar, 1000);
    EXPECT_LT(st.nearMaxDiff, 0.01);
    EXPECT_LT(st.farMaxPull, 1.25);
}

// A filter keeps the coverage: +inf (no fluid) stays +inf, fluid stays finite.
inline void expectCoverageKept(const Image<float>& in, const Image<float>& out) {
    ASSERT_EQ(in.size(), out.size());
    for (std::size_t i = 0; i < in.size(); ++i) ASSERT_EQ(std::isinf(in.pixels[i]), std::isinf(out.pixels[i])) << i;
}

// Largest |out/in - 1| over all pixels (both images finite where compared).
inline double maxRelativeChange(const Image<float>& in, const Image<float>& out) {
    double worst = 0.0;
    for (std::size_t i = 0; i < in.size(); ++i)
        worst = std::max(worst, std::fabs(double(out.pixels[i]) / in.pixels[i] - 1.0));
    return worst;
}

// A ball cut by the left image border: +inf around it, fluid at the border.
struct BorderBallScene {
    float r = 0.01f;
    Camera cam;
    Image<float> depth;
};
inline BorderBallScene borderBallScene() {
    BorderBallScene sc;
    const auto pts = ballOfParticles(glm::vec3(-0.45f, 0.0f, 0.0f), 0.15f, 2.0f * sc.r);
    sc.cam = faceOnCamera(glm::vec3(0.0f), 1.0f, 200, 150);
    sc.depth = cpu::splatDepth(sc.cam, pts, sc.r);
    return sc;
}

}  // namespace meniscus::test
