// Camera conventions of docs/conventions.md#conventions: focal length, pixel
// rays, row 0 at the top, auto-framing, validation.
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "meniscus/camera.h"
#include "meniscus/particles.h"

namespace camera_test_local {

using namespace meniscus;

namespace {
Camera lookAlongMinusZ() {
    Camera c;
    c.eye = {0, 0, 5};
    c.target = {0, 0, 0};
    c.width = 640;
    c.height = 480;
    c.fovYDegrees = 90.0f;
    return c;
}
}  // namespace

TEST(Camera, FocalLengthFromVerticalFovAndHeight) {
    Camera c = lookAlongMinusZ();
    EXPECT_NEAR(c.focalPx(), 240.0f, 1e-4f);  // (H/2)/tan(45 deg)
    c.fovYDegrees = 60.0f;
    EXPECT_NEAR(c.focalPx(), 240.0f / std::tan(glm::radians(30.0f)), 1e-3f);
}

TEST(Camera, PointOnOpticalAxisLandsOnImageCentre) {
    Camera c;
    c.eye = {1.3f, 2.0f, -0.7f};
    c.target = {-0.4f, 0.25f, 2.0f};
    c.width = 1280;
    c.height = 720;
    const glm::vec3 onAxis = c.eye + 3.7f * glm::normalize(c.target - c.eye);
    const glm::vec3 v = c.toView(onAxis);
    EXPECT_NEAR(-v.z, 3.7f, 1e-5f);  // eye depth is the distance along the axis
    const glm::vec2 px = c.projectView(v);
    EXPECT_NEAR(px.x, 640.0f, 1e-3f);
    EXPECT_NEAR(px.y, 360.0f, 1e-3f);
}

TEST(Camera, RowZeroIsTheTop) {
    const Camera c = lookAlongMinusZ();
    // A point above the axis (+y world = up) lands in the upper half: small row index.
    const glm::vec2 above = c.projectView(c.toView({0.0f, 1.0f, 0.0f}));
    EXPECT_LT(above.y, 240.0f);
    EXPECT_NEAR(above.y, 240.0f - 240.0f * 1.0f / 5.0f, 1e-3f);
    // A point to the right (+x) lands at a larger column.
    const glm::vec2 right = c.projectView(c.toView({1.0f, 0.0f, 0.0f}));
    EXPECT_GT(right.x, 320.0f);
    // The ray of the top-left pixel points up and to the left.
    const glm::vec3 d = c.pixelRay(0.5f, 0.5f);
    EXPECT_LT(d.x, 0.0f);
    EXPECT_GT(d.y, 0.0f);
    EXPECT_EQ(d.z, -1.0f);
}

TEST(Camera, PixelRayMatchesSpecFormula) {
    const Camera c = lookAlongMinusZ();
    const float f = c.focalPx();
    for (int j : {0, 17, 479})
        for (int i : {0, 301, 639}) {
            const glm::vec3 d = c.pixelRay(float(i) + 0.5f, float(j) + 0.5f);
            EXPECT_FLOAT_EQ(d.x, (float(i) + 0.5f - 320.0f) / f);
            EXPECT_FLOAT_EQ(d.y, -(float(j) + 0.5f - 240.0f) / f);
        }
}

TEST(Camera, UnprojectInvertsProject) {
    Camera c;
    c.eye = {2, 1, 3};
    c.target = {0, 0.3f, 0};
    for (const glm::vec3 w : {glm::vec3(0.1f, 0.2f, 0.3f), glm::vec3(-0.5f, 0.9f, 0.0f), glm::vec3(0.0f)}) {
        const glm::vec3 v = c.toView(w);
        const glm::vec2 px = c.projectView(v);
        const glm::vec3 back = c.toWorld(c.unproject(px.x, px.y, -v.z));
        EXPECT_NEAR(glm::length(back - w), 0.0f, 1e-5f);
    }
}

TEST(Camera, ViewBasisIsRightHanded) {
    Camera c;
    c.eye = {3, 2, 1};
    c.target = {0, 0, 0};
    EXPECT_NEAR(glm::dot(glm::cross(c.right(), c.trueUp()), c.back()), 1.0f, 1e-5f);
    EXPECT_GT(c.trueUp().y, 0.0f);  // +y stays up
}

namespace {
// A dam-break-like set: a low wide slab, a thin sheet up the right wall, and a
// few far-flung spray particles.
std::vector<glm::vec3> slabSheetAndSpray() {
    std::vector<glm::vec3> pts;
    for (int z = 0; z < 30; ++z)
        for (int x = 0; x < 80; ++x)
            for (int y = 0; y < 4; ++y) pts.push_back({-2.0f + 0.05f * float(x), 0.05f * float(y), -0.7f + 0.05f * float(z)});
    for (int z = 0; z < 30; ++z)
        for (int y = 0; y < 30; ++y) pts.push_back({1.95f, 0.2f + 0.05f * float(y), -0.7f + 0.05f * float(z)});
    for (int k = 0; k < 5; ++k) pts.push_back({0.3f * float(k), 8.0f + float(k), 0.0f});  // spray, far up
    return pts;
}
}  // namespace

TEST(Camera, AutoFrameFitsTheParticlesFromAThreeQuarterView) {
    const auto pts = slabSheetAndSpray();
    Camera base;
    base.width = 1280;
    base.height = 720;
    const float radius = 0.025f;
    const Camera c = autoFrameCamera(pts, radius, base);
    ASSERT_TRUE(validateCamera(c).ok());
    const glm::vec3 centre = computeBounds(std::span(pts).first(pts.size() - 5)).center();
    EXPECT_GT(c.eye.x, centre.x);  // from the front-right, above
    EXPECT_GT(c.eye.y, centre.y);
    EXPECT_GT(c.eye.z, 0.7f);
    float minX = 1e9f, maxX = -1e9f, minY = 1e9f, maxY = -1e9f;
    int outside = 0;
    for (const auto& p : pts) {
        const glm::vec3 v = c.toView(p);
        ASSERT_LT(-v.z, c.farM);
        const glm::vec2 q = c.projectView(v);
        if (-v.z <= c.nearM || q.x < 0 || q.x > 1280 || q.y < 0 || q.y > 720) {
            ++outside;
            continue;
        }
        minX = std::min(minX, q.x), maxX = std::max(maxX, q.x);
        minY = std::min(minY, q.y), maxY = std::max(maxY, q.y);
    }
    // The spray (5 of ~10k points) may be left out (0.1%); nothing else is.
    EXPECT_LE(outside, 5);
    // The fluid fills the frame up to the margin in one direction...
    const float fillX = (maxX - minX) / 1280.0f, fillY = (maxY - minY) / 720.0f;
    EXPECT_GT(std::max(fillX, fillY), 0.85f);
    EXPECT_LT(std::max(fillX, fillY), 0.95f);  // 90% fill, give or take the 0.1% left-out points
    // ...and sits in the middle.
    EXPECT_NEAR(0.5f * (minX + maxX), 640.0f, 16.0f);
    EXPECT_NEAR(0.5f * (minY + maxY), 360.0f, 16.0f);
}

// The automatic camera from a given azimuth and elevation looks along that
// direction and still frames the particles (90% fill).
TEST(Camera, AutoFrameFromAGivenDirection) {
    const auto pts = slabSheetAndSpray();
    Camera base;
    base.width = 640;
    base.height = 360;
    for (const auto& [az, el] : {std::pair{90.0f, 0.0f}, std::pair{-120.0f, 60.0f}, std::pair{0.0f, -30.0f}}) {
        const Camera c = autoFrameCamera(pts, 0.025f, base, nullptr, az, el);
        ASSERT_TRUE(validateCamera(c).ok());
        const glm::vec3 dir = glm::normalize(c.eye - c.target);
        const float a = glm::radians(az), e = glm::radians(el);
        EXPECT_NEAR(dir.x, std::sin(a) * std::cos(e), 1e-5f) << az << "," << el;
        EXPECT_NEAR(dir.y, std::sin(e), 1e-5f) << az << "," << el;
        EXPECT_NEAR(dir.z, std::cos(a) * std::cos(e), 1e-5f) << az << "," << el;
        float minX = 1e9f, maxX = -1e9f, minY = 1e9f, maxY = -1e9f;
        for (std::size_t i = 0; i + 5 < pts.size(); ++i) {  // without the spray
            const glm::vec2 q = c.projectView(c.toView(pts[i]));
            minX = std::min(minX, q.x), maxX = std::max(maxX, q.x);
            minY = std::min(minY, q.y), maxY = std::max(maxY, q.y);
        }
        EXPECT_GE(minX, -1.0f);
        EXPECT_LE(maxX, 641.0f);
        EXPECT_GE(minY, -1.0f);
        EXPECT_LE(maxY, 361.0f);
        EXPECT_GT(std::max((maxX - minX) / 640.0f, (maxY - minY) / 360.0f), 0.8f) << az << "," << el;
    }
    // The defaults are the three-quarter view's.
    const Camera d = autoFrameCamera(pts, 0.025f, base);
    const Camera g = autoFrameCamera(pts, 0.025f, base, nullptr, defaults::kAutoAzimuthDegrees,
                                     defaults::kAutoElevationDegrees);
    EXPECT_EQ(d.eye, g.eye);
    EXPECT_EQ(d.target, g.target);
}

TEST(Camera, AutoFrameScalesWithTheScene) {
    auto pts = slabSheetAndSpray();
    const Camera c1 = autoFrameCamera(pts, 0.025f, Camera{});
    for (auto& p : pts) p *= 10.0f;
    const Camera c10 = autoFrameCamera(pts, 0.25f, Camera{});
    EXPECT_NEAR(glm::length(c10.eye - 10.0f * c1.eye), 0.0f, 1e-3f);
    EXPECT_NEAR(glm::length(c10.target - 10.0f * c1.target), 0.0f, 1e-3f);
    EXPECT_NEAR(c10.nearM, 10.0f * c1.nearM, 1e-4f);
}

// Regression: one particle at x = 1e6 beside the fluid must move neither the
// target nor the distance, and is reported as left outside.
TEST(Camera, AutoFrameIgnoresAFarOutlierAndCountsIt) {
    auto pts = slabSheetAndSpray();
    std::size_t outside = 99;
    const Camera c = autoFrameCamera(pts, 0.025f, Camera{}, &outside);
    pts.push_back({1e6f, 0.0f, 0.0f});
    std::size_t outsideWith = 0;
    const Camera o = autoFrameCamera(pts, 0.025f, Camera{}, &outsideWith);
    ASSERT_TRUE(validateCamera(o).ok());
    const float dist = glm::length(c.eye - c.target);
    EXPECT_LT(glm::length(o.eye - c.eye), 0.02f * dist);
    EXPECT_LT(glm::length(o.target - c.target), 0.02f * dist);
    EXPECT_EQ(outsideWith, outside + 1);
}

TEST(Camera, AutoFrameOfASingleParticleSeesIt) {
    const glm::vec3 p{1.0f, 2.0f, 3.0f};
    const Camera c = autoFrameCamera(std::span(&p, 1), 0.1f, Camera{});
    ASSERT_TRUE(validateCamera(c).ok());
    const glm::vec2 q = c.projectView(c.toView(p));
    EXPECT_NEAR(q.x, 640.0f, 1.0f);
    EXPECT_NEAR(q.y, 360.0f, 1.0f);
}

TEST(Camera, ValidationRejectsDegenerateCameras) {
    Camera c = lookAlongMinusZ();
    EXPECT_TRUE(validateCamera(c).ok());
    Camera same = c;
    same.target = same.eye;
    EXPECT_FALSE(validateCamera(same).ok());
    Camera parallel = c;
    parallel.up = {0, 0, 1};
    EXPECT_FALSE(validateCamera(parallel).ok());
    EXPECT_NE(validateCamera(parallel).error().message.find("up"), std::string::npos);
    Camera fov = c;
    fov.fovYDegrees = 180.0f;
    EXPECT_FALSE(validateCamera(fov).ok());
    Camera nan = c;
    nan.eye.x = std::nanf("");
    EXPECT_FALSE(validateCamera(nan).ok());
    Camera size = c;
    size.width = 0;
    EXPECT_FALSE(validateCamera(size).ok());
}

// The viewer's orbit: the target stays, the distance scales only with zoom,
// a positive azimuth moves the eye toward the camera's right, a full turn comes
// back, the elevation stops short of the pole, and the near plane follows a zoom in.
TEST(Camera, OrbitTurnsAroundTheTarget) {
    Camera c = lookAlongMinusZ();
    c.target = {1, 2, 3};
    c.eye = c.target + glm::vec3(0, 0, 5);
    c.nearM = 1.0f;
    c.farM = 100.0f;
    const Camera turned = orbitCamera(c, 90.0f, 0.0f, 1.0f);
    EXPECT_EQ(turned.target, c.target);
    EXPECT_NEAR(glm::length(turned.eye - turned.target), 5.0f, 1e-5f);
    EXPECT_NEAR(turned.eye.x - c.target.x, 5.0f, 1e-5f);  // toward the camera's right, +x
    EXPECT_NEAR(turned.eye.z - c.target.z, 0.0f, 1e-5f);
    EXPECT_TRUE(validateCamera(turned).ok());
    const Camera around = orbitCamera(orbitCamera(turned, 200.0f, 0.0f, 1.0f), 70.0f, 0.0f, 1.0f);
    EXPECT_NEAR(glm::length(around.eye - c.eye), 0.0f, 1e-4f);

    const Camera up = orbitCamera(c, 0.0f, 30.0f, 1.0f);
    EXPECT_NEAR(up.eye.y - c.target.y, 5.0f * std::sin(glm::radians(30.0f)), 1e-5f);
    const Camera pole = orbitCamera(c, 0.0f, 500.0f, 1.0f);
    EXPECT_NEAR(std::asin((pole.eye.y - c.target.y) / 5.0f), glm::radians(89.0f), 1e-4f);
    EXPECT_TRUE(validateCamera(pole).ok());

    const Camera in = orbitCamera(c, 0.0f, 0.0f, 0.5f);
    EXPECT_NEAR(glm::length(in.eye - in.target), 2.5f, 1e-5f);
    EXPECT_NEAR(in.nearM, 2.5e-3f, 1e-7f);
    EXPECT_EQ(in.farM, c.farM);
    const Camera out = orbitCamera(c, 0.0f, 0.0f, 4.0f);
    EXPECT_NEAR(glm::length(out.eye - out.target), 20.0f, 1e-4f);
    EXPECT_EQ(out.farM, 4.0f * c.farM);
    EXPECT_EQ(out.width, c.width);
    EXPECT_EQ(out.fovYDegrees, c.fovYDegrees);
}

// The camera's defaults are params.h's, and validateCamera's size cap is the
// CLI's (defaults::kMaxImageSizePx).
TEST(Camera, DefaultsAndSizeCapComeFromParams) {
    const Camera c;
    EXPECT_EQ(c.fovYDegrees, defaults::kFovYDegrees);
    Camera big = c;
    big.width = defaults::kMaxImageSizePx;
    EXPECT_TRUE(validateCamera(big).ok());
    big.width = defaults::kMaxImageSizePx + 1;
    EXPECT_FALSE(validateCamera(big).ok());
}
// An application's glm::lookAt and glm::perspective give back the camera that
// projects every point to the pixel GL puts it at (window x, and y counted
// from the top), with the same near and far planes.
TEST(CameraFromGlMatrices, SeesWhatTheMatricesSee) {
    const int W = 320, H = 180;
    const glm::vec3 eye(1.5f, 0.8f, 2.5f), target(0.2f, 0.1f, -0.3f), up(0.1f, 1.0f, 0.0f);
    const glm::mat4 view = glm::lookAt(eye, target, up);
    const glm::mat4 proj = glm::perspective(glm::radians(50.0f), float(W) / float(H), 0.05f, 40.0f);
    auto c = cameraFromGlMatrices(view, proj, W, H);
    ASSERT_TRUE(c.ok()) << c.error().describe();
    EXPECT_NEAR(c->fovYDegrees, 50.0f, 1e-4f);
    EXPECT_NEAR(c->nearM, 0.05f, 1e-6f);
    EXPECT_NEAR(c->farM, 40.0f, 4e-3f);  // the matrix's float P22 + 1 holds 1e-4 of it
    EXPECT_EQ(c->width, W);
    EXPECT_EQ(c->height, H);
    for (const glm::vec3 p : {glm::vec3(0.0f), glm::vec3(0.5f, -0.2f, 0.3f), glm::vec3(-0.7f, 0.6f, -1.0f)}) {
        const glm::vec4 clip = proj * view * glm::vec4(p, 1.0f);
        const glm::vec3 ndc = glm::vec3(clip) / clip.w;
        const glm::vec2 window((ndc.x + 1.0f) * 0.5f * W, (1.0f - (ndc.y + 1.0f) * 0.5f) * H);
        const glm::vec3 v = c->toView(p);
        const glm::vec2 px = c->projectView(v);
        EXPECT_NEAR(px.x, window.x, 2e-3f);
        EXPECT_NEAR(px.y, window.y, 2e-3f);
        EXPECT_NEAR(-v.z, clip.w, 1e-4f);  // the eye depth is the clip w
    }
}

TEST(CameraFromGlMatrices, WhatItCannotDescribeIsAnErrorSayingWhy) {
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 3), glm::vec3(0.0f), glm::vec3(0, 1, 0));
    const glm::mat4 proj = glm::perspective(glm::radians(45.0f), 2.0f, 0.1f, 10.0f);
    auto expectError = [](const Result<Camera>& c, const std::string& words) {
        ASSERT_FALSE(c.ok());
        EXPECT_NE(c.error().describe().find(words), std::string::npos) << c.error().describe();
    };
    expectError(cameraFromGlMatrices(view, glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f, 10.0f), 200, 100), "perspective");
    expectError(cameraFromGlMatrices(view, glm::frustum(-0.1f, 0.3f, -0.1f, 0.1f, 0.1f, 10.0f), 200, 100), "off-centre");
    expectError(cameraFromGlMatrices(view, proj, 100, 100), "aspect");
    expectError(cameraFromGlMatrices(glm::scale(view, glm::vec3(2.0f)), proj, 200, 100), "rotation and a translation");
    expectError(cameraFromGlMatrices(glm::scale(view, glm::vec3(-1.0f, 1.0f, 1.0f)), proj, 200, 100), "mirrors");
    expectError(cameraFromGlMatrices(view, glm::infinitePerspective(glm::radians(45.0f), 2.0f, 0.1f), 200, 100), "far");
    expectError(cameraFromGlMatrices(view, proj, 0, 100), "no pixels");
    glm::mat4 bad = view;
    bad[3][0] = NAN;
    expectError(cameraFromGlMatrices(bad, proj, 200, 100), "finite");
}

}  // namespace camera_test_local
