// Camera motion of rendered sequences (include/meniscus/camera_path.h): the
// key-framed path passes through every key, is C1, holds its ends and is
// still for one key; bad paths are named; an orbit turns the eye about +y
// through the target by orbit * i / fps degrees, a turntable by 360 i / N.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "meniscus/camera_path.h"

namespace camera_path_test_local {

using namespace meniscus;

namespace {

CameraKey key(double t, glm::vec3 eye, glm::vec3 target, float fov) { return {t, eye, target, fov}; }

// Uneven times, so the tangents' time scaling matters.
std::vector<CameraKey> somePath() {
    return {key(0.0, {3, 1, 0}, {0, 0, 0}, 40), key(0.5, {0, 2, 3}, {0.1f, 0.2f, 0}, 30),
            key(2.0, {-3, 1, 0}, {0, 0.5f, 0}, 50), key(2.25, {0, 1.5f, -2}, {0, 0, 0.3f}, 45)};
}

// Eye, target and fov as one 7-vector, for distances.
double distance(const CameraKey& a, const CameraKey& b) {
    return glm::length(glm::dvec3(a.eye - b.eye)) + glm::length(glm::dvec3(a.target - b.target)) +
           std::abs(double(a.fovYDegrees - b.fovYDegrees));
}

// d/dt of the path's eye by a central difference in double steps around t.
glm::dvec3 eyeVelocity(const std::vector<CameraKey>& p, double t, double h) {
    return (glm::dvec3(cameraPathAt(p, t + h).eye) - glm::dvec3(cameraPathAt(p, t - h).eye)) / (2.0 * h);
}

Camera startCamera() {
    Camera c;
    c.eye = {2.0f, 1.5f, 3.0f};
    c.target = {0.3f, 0.4f, -0.2f};
    c.width = 96;
    c.height = 64;
    return c;
}

}  // namespace

TEST(CameraPath, PassesThroughEveryKeyExactly) {
    const auto p = somePath();
    for (const CameraKey& k : p) {
        const CameraKey at = cameraPathAt(p, k.timeS);
        EXPECT_EQ(at.eye, k.eye) << k.timeS;
        EXPECT_EQ(at.target, k.target) << k.timeS;
        EXPECT_EQ(at.fovYDegrees, k.fovYDegrees) << k.timeS;
    }
}

TEST(CameraPath, IsContinuousWithAContinuousVelocity) {
    const auto p = somePath();
    // No jump anywhere: samples 1 ms apart are close (the keys are metres and
    // degrees apart; the fastest stretch moves about 0.05 per ms).
    for (double t = -0.1; t < 2.4; t += 0.001)
        EXPECT_LT(distance(cameraPathAt(p, t), cameraPathAt(p, t + 0.001)), 0.1) << t;
    // C1: at each inner key the velocity just before equals the one just after
    // (one-sided differences over 1e-4 s, agreeing to O(h) of the curvature).
    const double h = 1e-4;
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
        const double t = p[k].timeS;
        const glm::dvec3 before = (glm::dvec3(cameraPathAt(p, t).eye) - glm::dvec3(cameraPathAt(p, t - h).eye)) / h;
        const glm::dvec3 after = (glm::dvec3(cameraPathAt(p, t + h).eye) - glm::dvec3(cameraPathAt(p, t).eye)) / h;
        EXPECT_LT(glm::length(before - after), 0.02 * glm::length(before)) << "key " << k;
        // And it is the Catmull-Rom tangent: the neighbours' difference over their time span.
        const glm::dvec3 expected = (glm::dvec3(p[k + 1].eye) - glm::dvec3(p[k - 1].eye)) / (p[k + 1].timeS - p[k - 1].timeS);
        EXPECT_LT(glm::length(eyeVelocity(p, t, h) - expected), 1e-2) << "key " << k;
    }
}

TEST(CameraPath, HoldsTheEndKeysOutsideItsTimes) {
    const auto p = somePath();
    for (double t : {-5.0, -1e-9, 0.0}) EXPECT_EQ(cameraPathAt(p, t), p.front()) << t;
    for (double t : {2.25, 2.2500001, 100.0}) {
        const CameraKey at = cameraPathAt(p, t);
        EXPECT_EQ(at.eye, p.back().eye) << t;
        EXPECT_EQ(at.fovYDegrees, p.back().fovYDegrees) << t;
    }
}

TEST(CameraPath, OneKeyIsAStillCameraAndTwoAreAStraightLine) {
    const std::vector<CameraKey> one{key(1.0, {1, 2, 3}, {0, 0, 0}, 35)};
    for (double t : {-1.0, 1.0, 7.5}) EXPECT_EQ(cameraPathAt(one, t).eye, one[0].eye);
    CameraMotion still;
    still.path = one;
    still.frames = 10;
    EXPECT_FALSE(still.moves());
    EXPECT_EQ(cameraForFrame(startCamera(), still, 7).fovYDegrees, 35.0f);
    // Two keys: both tangents are the chord, so the curve is the segment.
    const std::vector<CameraKey> two{key(0.0, {0, 0, 0}, {0, 0, -1}, 40), key(2.0, {4, 2, 0}, {0, 0, -1}, 60)};
    const CameraKey mid = cameraPathAt(two, 0.5);
    EXPECT_NEAR(mid.eye.x, 1.0f, 1e-6f);
    EXPECT_NEAR(mid.eye.y, 0.5f, 1e-6f);
    EXPECT_NEAR(mid.fovYDegrees, 45.0f, 1e-4f);
}

TEST(CameraPath, BadPathsAreNamed) {
    EXPECT_NE(checkCameraPath({}).find("at least one key"), std::string::npos);
    EXPECT_EQ(checkCameraPath(somePath()), "");
    auto p = somePath();
    p[2].timeS = 0.5;  // the same time as key 2
    EXPECT_NE(checkCameraPath(p).find("key 3"), std::string::npos) << checkCameraPath(p);
    p = somePath();
    p[1].fovYDegrees = 180.0f;
    EXPECT_NE(checkCameraPath(p).find("key 2: fov"), std::string::npos) << checkCameraPath(p);
    p = somePath();
    p[0].eye.x = NAN;
    EXPECT_NE(checkCameraPath(p).find("key 1"), std::string::npos) << checkCameraPath(p);
}

TEST(CameraPath, OrbitTurnsTheEyeAboutTheVerticalThroughTheTarget) {
    const Camera start = startCamera();
    CameraMotion orbit;
    orbit.orbitDegPerS = 45.0;
    orbit.fps = 24.0;
    orbit.frames = 100;
    ASSERT_TRUE(orbit.moves());
    EXPECT_EQ(cameraForFrame(start, orbit, 0), start);  // frame 0 is the start camera, exactly
    for (std::size_t i : {1u, 7u, 24u, 99u}) {
        const Camera c = cameraForFrame(start, orbit, i);
        // Independently: glm's rotation matrix about +y by 45 i / 24 degrees.
        const float angle = glm::radians(float(45.0 * double(i) / 24.0));
        const glm::vec3 expected =
            start.target + glm::vec3(glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0, 1, 0)) *
                                     glm::vec4(start.eye - start.target, 0.0f));
        EXPECT_LT(glm::length(c.eye - expected), 1e-5f) << i;
        EXPECT_EQ(c.target, start.target);
        EXPECT_EQ(c.eye.y, start.eye.y);  // elevation kept
        EXPECT_NEAR(glm::length(c.eye - c.target), glm::length(start.eye - start.target), 1e-5f);  // distance kept
        EXPECT_EQ(c.width, start.width);
        EXPECT_EQ(c.fovYDegrees, start.fovYDegrees);
    }
    // 8 s at 45 deg/s: a whole turn, back where it started.
    EXPECT_LT(glm::length(cameraForFrame(start, orbit, 192).eye - start.eye), 1e-5f);
    // Counter-clockwise seen from above: +x turns toward -z.
    Camera onX = start;
    onX.target = glm::vec3(0.0f);
    onX.eye = {1.0f, 0.0f, 0.0f};
    orbit.fps = 2.0;  // frame 1 at 0.5 s: 22.5 degrees
    EXPECT_LT(cameraForFrame(onX, orbit, 1).eye.z, -0.3f);
}

TEST(CameraPath, TurntableIsOneTurnOverTheFrames) {
    const Camera start = startCamera();
    CameraMotion table;
    table.turntable = true;
    table.frames = 8;
    table.fps = 1000.0;  // the frame rate does not matter
    ASSERT_TRUE(table.moves());
    EXPECT_EQ(cameraForFrame(start, table, 0), start);
    const glm::vec3 half = cameraForFrame(start, table, 4).eye;  // 180 degrees: the opposite side
    EXPECT_LT(glm::length((half - start.target) + (start.eye - start.target) * glm::vec3(1, -1, 1)), 1e-5f);
    EXPECT_LT(glm::length(cameraForFrame(start, table, 8).eye - start.eye), 1e-5f);  // frame N would close the turn
    table.frames = 1;
    EXPECT_FALSE(table.moves());
}

TEST(CameraPath, AnOrbitTurnsThePathsEye) {
    // The path gives eye and target at the frame's time; the orbit turns that eye.
    CameraMotion m;
    m.path = somePath();
    m.orbitDegPerS = 90.0;
    m.fps = 4.0;
    const Camera c = cameraForFrame(startCamera(), m, 3);  // 0.75 s: 67.5 degrees
    const CameraKey k = cameraPathAt(m.path, 0.75);
    EXPECT_EQ(c.target, k.target);
    EXPECT_EQ(c.fovYDegrees, k.fovYDegrees);
    EXPECT_EQ(c.eye, turnAboutVertical(k.eye, k.target, 67.5));
    EXPECT_NE(c.eye, k.eye);
}
}  // namespace camera_path_test_local
