// Camera paths and turns about the vertical (include/meniscus/camera_path.h).
// The path is a cubic Hermite spline with Catmull-Rom tangents measured in
// time, so it is C1 however unevenly the keys are spaced, and it reaches each
// key exactly (at a key the curve is evaluated at s = 0 of the segment that
// starts there, where only that key's weight is non-zero).
#include "meniscus/camera_path.h"
#include "shared/finite.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace meniscus {

namespace {


std::string seconds(double t) {
    std::ostringstream out;
    out << t << " s";
    return out.str();
}

// What the spline interpolates, in double precision: eye, target, fov.
struct PathPoint {
    glm::dvec3 eye, target;
    double fov;
};
PathPoint pointOf(const CameraKey& k) { return {glm::dvec3(k.eye), glm::dvec3(k.target), double(k.fovYDegrees)}; }
PathPoint operator-(const PathPoint& a, const PathPoint& b) { return {a.eye - b.eye, a.target - b.target, a.fov - b.fov}; }
PathPoint operator*(double s, const PathPoint& a) { return {s * a.eye, s * a.target, s * a.fov}; }
PathPoint operator+(const PathPoint& a, const PathPoint& b) { return {a.eye + b.eye, a.target + b.target, a.fov + b.fov}; }

// The tangent (per second) at key k: central difference over its two
// neighbours, one-sided at the ends.
PathPoint tangent(std::span<const CameraKey> keys, std::size_t k) {
    const std::size_t lo = k > 0 ? k - 1 : k, hi = k + 1 < keys.size() ? k + 1 : k;
    return (1.0 / (keys[hi].timeS - keys[lo].timeS)) * (pointOf(keys[hi]) - pointOf(keys[lo]));
}

}  // namespace

std::string checkCameraPath(std::span<const CameraKey> keys) {
    if (keys.empty()) return "a camera path needs at least one key";
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const CameraKey& c = keys[k];
        const std::string which = "key " + std::to_string(k + 1);
        if (!std::isfinite(c.timeS) || !finite3(c.eye) || !finite3(c.target))
            return which + ": time, eye and target must be finite numbers";
        if (!(c.fovYDegrees > 0.0f && c.fovYDegrees < 180.0f)) return which + ": fov must be in (0, 180) degrees";
        if (k > 0 && !(c.timeS > keys[k - 1].timeS))
            return which + ": time " + seconds(c.timeS) + " is not after the key before (" + seconds(keys[k - 1].timeS) +
                   "); keys go in increasing time";
    }
    return {};
}

CameraKey cameraPathAt(std::span<const CameraKey> keys, double timeS) {
    if (keys.size() == 1 || !(timeS > keys.front().timeS)) return keys.front();
    if (timeS >= keys.back().timeS) return keys.back();
    // The segment [t_k, t_k+1) holding timeS.
    const auto after = std::upper_bound(keys.begin(), keys.end(), timeS,
                                        [](double t, const CameraKey& c) { return t < c.timeS; });
    const std::size_t k = std::size_t(after - keys.begin()) - 1;
    const double h = keys[k + 1].timeS - keys[k].timeS, s = (timeS - keys[k].timeS) / h;
    if (s == 0.0) return keys[k];
    // Hermite basis on s in [0, 1]; tangents scaled from per second to per segment.
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    const PathPoint p = h00 * pointOf(keys[k]) + (h10 * h) * tangent(keys, k) + h01 * pointOf(keys[k + 1]) +
                        (h11 * h) * tangent(keys, k + 1);
    CameraKey out;
    out.timeS = timeS;
    out.eye = glm::vec3(p.eye);
    out.target = glm::vec3(p.target);
    // The fov may overshoot a little between keys; it stays a real one.
    out.fovYDegrees = float(std::clamp(p.fov, 1.0, 179.0));
    return out;
}

glm::vec3 turnAboutVertical(const glm::vec3& point, const glm::vec3& centre, double degrees) {
    if (degrees == 0.0) return point;
    const double a = glm::radians(degrees), c = std::cos(a), s = std::sin(a);
    const double x = double(point.x) - double(centre.x), z = double(point.z) - double(centre.z);
    // Rotation about +y: x' = x cos + z sin, z' = -x sin + z cos; the height stays exactly.
    return {float(double(centre.x) + c * x + s * z), point.y, float(double(centre.z) - s * x + c * z)};
}

bool CameraMotion::moves() const {
    return path.size() > 1 || orbitDegPerS != 0.0 || (turntable && frames > 1);
}

Camera cameraForFrame(const Camera& start, const CameraMotion& motion, std::size_t i) {
    Camera cam = start;
    const double timeS = double(i) / motion.fps;
    if (!motion.path.empty()) {
        const CameraKey k = cameraPathAt(motion.path, timeS);
        cam.eye = k.eye;
        cam.target = k.target;
        cam.fovYDegrees = k.fovYDegrees;
    }
    const double degrees = motion.turntable ? 360.0 * double(i) / double(std::max<std::size_t>(motion.frames, 1))
                                            : motion.orbitDegPerS * timeS;
    cam.eye = turnAboutVertical(cam.eye, cam.target, degrees);
    return cam;
}

}  // namespace meniscus
