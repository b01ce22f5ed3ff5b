// Camera math of docs/conventions.md#conventions and the automatic
// three-quarter framing.
#include "meniscus/camera.h"

#include <algorithm>
#include <string>
#include <vector>
#include <cmath>

#include "meniscus/params.h"
#include "meniscus/particles.h"
#include "shared/finite.h"

namespace meniscus {

namespace {
}  // namespace

float Camera::focalPx() const {
    return 0.5f * float(height) / std::tan(0.5f * glm::radians(fovYDegrees));
}

glm::vec3 Camera::back() const { return glm::normalize(eye - target); }
glm::vec3 Camera::right() const { return glm::normalize(glm::cross(up, back())); }
glm::vec3 Camera::trueUp() const { return glm::cross(back(), right()); }

glm::vec3 Camera::toView(const glm::vec3& world) const {
    const glm::vec3 d = world - eye;
    return {glm::dot(d, right()), glm::dot(d, trueUp()), glm::dot(d, back())};
}

glm::vec3 Camera::dirToWorld(const glm::vec3& v) const { return v.x * right() + v.y * trueUp() + v.z * back(); }
glm::vec3 Camera::toWorld(const glm::vec3& view) const { return eye + dirToWorld(view); }

glm::vec3 Camera::pixelRay(float px, float py) const {
    const float f = focalPx();
    return {(px - 0.5f * float(width)) / f, -(py - 0.5f * float(height)) / f, -1.0f};
}

glm::vec2 Camera::projectView(const glm::vec3& v) const {
    const float f = focalPx();
    const float z = -v.z;  // eye depth
    return {0.5f * float(width) + f * v.x / z, 0.5f * float(height) - f * v.y / z};
}

Result<Camera> cameraFromGlMatrices(const glm::mat4& view, const glm::mat4& projection, int width, int height) {
    const char* what = "the host's camera";
    if (width <= 0 || height <= 0) return makeError(what, "the picture has no pixels");
    for (int c = 0; c < 4; ++c)
        if (!finite3(glm::vec3(view[c])) || !finite3(glm::vec3(projection[c])) || !std::isfinite(view[c][3]) ||
            !std::isfinite(projection[c][3]))
            return makeError(what, "the view and projection matrices must be finite");
    // The projection, P[column][row]: glm::perspective(fovy, aspect, n, f) is
    // P00 = 1 / (aspect tan(fovy / 2)), P11 = 1 / tan(fovy / 2),
    // P22 = -(f + n) / (f - n), P32 = -2 f n / (f - n), P23 = -1, zeros elsewhere.
    const glm::mat4& P = projection;
    const float tol = 1e-5f;
    const bool perspective = std::abs(P[2][3] + 1.0f) <= tol && std::abs(P[3][3]) <= tol &&
                             std::abs(P[0][3]) <= tol && std::abs(P[1][3]) <= tol;
    if (!perspective || !(P[0][0] > 0.0f) || !(P[1][1] > 0.0f))
        return makeError(what, "the projection is not a perspective one (glm::perspective, gluPerspective)");
    if (std::abs(P[2][0]) > tol || std::abs(P[2][1]) > tol || std::abs(P[1][0]) > tol || std::abs(P[0][1]) > tol)
        return makeError(what, "the projection's frustum is off-centre or skewed; only a symmetric one is supported");
    const float aspect = P[1][1] / P[0][0], want = float(width) / float(height);
    if (std::abs(aspect - want) > 1e-3f * want)
        return makeError(what, "the projection's aspect " + std::to_string(aspect) + " is not the picture's " +
                                   std::to_string(width) + " / " + std::to_string(height) + " (pixels must be square)");
    // In double: P22 + 1 is small for a far plane far beyond the near one.
    const float nearM = float(double(P[3][2]) / (double(P[2][2]) - 1.0)),
                farM = float(double(P[3][2]) / (double(P[2][2]) + 1.0));
    if (!std::isfinite(nearM) || !std::isfinite(farM) || !(nearM > 0.0f) || !(farM > nearM))
        return makeError(what, "the projection's near and far planes are not 0 < near < far, both finite "
                               "(a far plane at infinity or a reversed depth range is not supported)");
    // The view: world -> eye. Its inverse's columns are the camera's axes and
    // its position in the world.
    const glm::mat3 R(view);
    const glm::mat3 RRt = R * glm::transpose(R);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (std::abs(RRt[i][j] - (i == j ? 1.0f : 0.0f)) > 1e-4f || std::abs(view[i][3]) > tol)
                return makeError(what, "the view matrix is not a rotation and a translation (it scales, shears "
                                       "or projects)");
    if (glm::determinant(R) <= 0.0f) return makeError(what, "the view matrix mirrors the world");
    const glm::mat4 inv = glm::inverse(view);
    Camera c;
    c.eye = glm::vec3(inv[3]);
    const glm::vec3 back = glm::normalize(glm::vec3(inv[2]));
    c.target = c.eye - back;  // one metre ahead: only the direction matters
    c.up = glm::normalize(glm::vec3(inv[1]));
    c.fovYDegrees = float(glm::degrees(2.0 * std::atan(1.0 / double(P[1][1]))));
    c.nearM = nearM;
    c.farM = farM;
    c.width = width;
    c.height = height;
    if (auto st = validateCamera(c); !st) return st.error();
    return c;
}

Status validateCamera(const Camera& c) {
    if (!finite3(c.eye) || !finite3(c.target) || !finite3(c.up))
        return makeError("", "camera: eye, target and up must be finite numbers");
    if (glm::length(c.eye - c.target) <= 0.0f) return makeError("", "camera: eye and target are the same point");
    if (glm::length(c.up) <= 0.0f) return makeError("", "camera: up vector is zero");
    const glm::vec3 fwd = glm::normalize(c.target - c.eye);
    if (glm::length(glm::cross(fwd, glm::normalize(c.up))) < 1e-4f)
        return makeError("", "camera: up vector is parallel to the view direction; choose another --up");
    if (!(c.fovYDegrees > 0.0f && c.fovYDegrees < 180.0f))
        return makeError("", "camera: field of view must be between 0 and 180 degrees");
    if (!(c.nearM > 0.0f && c.farM > c.nearM)) return makeError("", "camera: need 0 < near < far");
    if (c.width <= 0 || c.height <= 0 || c.width > defaults::kMaxImageSizePx || c.height > defaults::kMaxImageSizePx)
        return makeError("", "camera: image size must be between 1 and " + std::to_string(defaults::kMaxImageSizePx) +
                                 " pixels");
    return okStatus();
}

namespace {

// The q-quantile (0..1) of v; v is reordered.
float quantile(std::vector<float>& v, float q) {
    const std::size_t k = std::min(v.size() - 1, std::size_t(q * float(v.size() - 1) + 0.5f));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}

}  // namespace

// The box holding all but the outermost `fraction` of the points on each
// axis, so one far outlier cannot stretch it.
Bounds robustBounds(const std::vector<glm::vec3>& pts, float fraction) {
    Bounds b;
    std::vector<float> v(pts.size());
    for (int a = 0; a < 3; ++a) {
        for (std::size_t i = 0; i < pts.size(); ++i) v[i] = pts[i][a];
        b.min[a] = quantile(v, 0.5f * fraction);
        b.max[a] = quantile(v, 1.0f - 0.5f * fraction);
    }
    return b;
}

Camera autoFrameCamera(std::span<const glm::vec3> points, float radiusM, const Camera& base, std::size_t* outside,
                       float azimuthDegrees, float elevationDegrees) {
    Camera cam = base;
    cam.up = {0.0f, 1.0f, 0.0f};
    // At most ~kAutoFramePoints points decide the framing (an even stride through the set).
    std::vector<glm::vec3> pts;
    const std::size_t stride = std::max<std::size_t>(1, points.size() / defaults::kAutoFramePoints);
    for (std::size_t i = 0; i < points.size(); i += stride)
        if (finite3(points[i])) pts.push_back(points[i]);
    if (pts.empty()) pts = {glm::vec3(-1.0f), glm::vec3(1.0f)};
    const float pad = std::isfinite(radiusM) ? std::max(radiusM, 0.0f) : 0.0f;

    const float az = glm::radians(std::isfinite(azimuthDegrees) ? azimuthDegrees : defaults::kAutoAzimuthDegrees);
    const float el = glm::radians(std::clamp(std::isfinite(elevationDegrees) ? elevationDegrees
                                                                             : defaults::kAutoElevationDegrees,
                                             -89.0f, 89.0f));
    const glm::vec3 toEye{std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
    const glm::vec3 fwd = -toEye;
    const glm::vec3 right = glm::normalize(glm::cross(fwd, cam.up));
    const glm::vec3 up = glm::cross(right, fwd);
    const float tanY = std::tan(0.5f * glm::radians(cam.fovYDegrees)) * defaults::kAutoFill;
    const float tanX = tanY * float(cam.width) / float(cam.height);
    const float keep = 1.0f - defaults::kAutoOutlierFraction;

    const Bounds box = robustBounds(pts, defaults::kAutoOutlierFraction);
    std::vector<float> need(pts.size()), sx(pts.size()), sy(pts.size());
    // Distance: each point needs |x| + pad <= tan * (d + z) in x and in y.
    auto fitDistance = [&] {
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const glm::vec3 c = pts[i] - cam.target;
            const float x = glm::dot(c, right), y = glm::dot(c, up), z = glm::dot(c, fwd);
            need[i] = std::max((std::abs(x) + pad) / tanX - z, (std::abs(y) + pad) / tanY - z);
        }
        const float size = glm::length(box.extent()) + pad;
        const float d = quantile(need, keep);
        return d > 1e-3f * size ? d : std::max(size, 1e-3f);
    };
    // Centre: shift the target so the framed content's image extent is symmetric.
    auto centre = [&](float d) {
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const glm::vec3 c = pts[i] - cam.target;
            const float depth = std::max(d + glm::dot(c, fwd), 1e-6f * d);
            sx[i] = glm::dot(c, right) / depth;
            sy[i] = glm::dot(c, up) / depth;
        }
        const float lo = 0.5f * (1.0f - keep);
        const float cx = 0.5f * (quantile(sx, lo) + quantile(sx, 1.0f - lo));
        const float cy = 0.5f * (quantile(sy, lo) + quantile(sy, 1.0f - lo));
        cam.target += d * (cx * right + cy * up);
    };
    cam.target = box.center();
    for (int iter = 0; iter < 6; ++iter) centre(fitDistance());
    const float dist = fitDistance();  // last: the fit holds exactly for the final target
    cam.eye = cam.target + dist * toEye;
    if (outside) {
        // Points whose sphere leaves the whole image (not just the filled part).
        const float fill = defaults::kAutoFill;
        *outside = 0;
        for (const glm::vec3& p : pts) {
            const glm::vec3 c = p - cam.target;
            const float x = glm::dot(c, right), y = glm::dot(c, up), z = glm::dot(c, fwd);
            if (std::max((std::abs(x) + pad) * fill / tanX - z, (std::abs(y) + pad) * fill / tanY - z) > dist)
                ++*outside;
        }
        *outside *= stride;  // of all the points, when they were sampled
    }

    // Clip range around the particles, so a scaled scene gets a scaled range.
    // The near plane follows the framed points (left-out spray may even be
    // behind the eye); the far plane keeps everything.
    float farthest = dist;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        need[i] = dist + glm::dot(pts[i] - cam.target, fwd);
        farthest = std::max(farthest, need[i] + pad);
    }
    const float nearest = quantile(need, 1.0f - keep) - pad;
    cam.nearM = std::max(0.5f * nearest, 1e-4f * dist);
    cam.farM = std::max(10.0f * farthest, cam.nearM * 2.0f);
    return cam;
}

Camera orbitCamera(const Camera& camera, float azimuthDegrees, float elevationDegrees, float zoom) {
    constexpr float kMaxElevation = glm::radians(89.0f);
    Camera cam = camera;
    const glm::vec3 u = glm::normalize(camera.up);
    const glm::vec3 offset = camera.eye - camera.target;
    const float dist = glm::length(offset);
    const glm::vec3 dir = offset / dist;
    // The direction to the eye as an elevation and a horizontal unit vector
    // (not zero: a valid camera's up is not along its view direction).
    const float elevation = std::asin(std::clamp(glm::dot(dir, u), -1.0f, 1.0f));
    glm::vec3 h = glm::normalize(dir - glm::dot(dir, u) * u);
    // Turn h about u (Rodrigues, h perpendicular to u): toward the right of a
    // camera looking back along -h is toward u x h.
    const float a = glm::radians(azimuthDegrees);
    h = std::cos(a) * h + std::sin(a) * glm::cross(u, h);
    const float e = std::clamp(elevation + glm::radians(elevationDegrees), -kMaxElevation, kMaxElevation);
    const float newDist = dist * zoom;
    cam.eye = camera.target + newDist * (std::cos(e) * h + std::sin(e) * u);
    cam.nearM = std::min(camera.nearM, 1e-3f * newDist);
    cam.farM = camera.farM * std::max(zoom, 1.0f);
    return cam;
}

}  // namespace meniscus
