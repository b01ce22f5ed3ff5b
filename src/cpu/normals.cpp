// CPU normals stage, SPEC §3.6. After van der Laan, Green & Sainz 2009
// (US 8,947,430, eqs. 3-6) and Cords & Staadt 2008 ("Instant Liquids" §2.3,
// perspective-correct normals): every fluid pixel is back-projected with its
// smoothed eye depth to the view-space point P = z * ray(x+1/2, y+1/2), and
// n = normalize(dP/dx × dP/dy).
//
// Choices:
//  - The exact inverse projection is used (the patent drops the W terms of its
//    eq. 5; keeping them costs nothing and makes a plane's normal exact).
//  - Per axis: the central difference where both neighbours continue the
//    surface; at a discontinuity (neighbour +inf, outside the image, |dz| above
//    jumpRadii * r) or where the two one-sided differences disagree by more than
//    that, the one-sided difference with the smaller |dz| (patent), so the
//    normals of separate bodies never mix.
//  - With no usable neighbour along an axis, the tangent is the screen axis
//    made perpendicular to the view ray, i.e. the surface is taken to face the
//    camera along that axis (a one-pixel sliver faces the eye exactly).
//  - Image rows grow downward while view-space y grows upward, so the "y"
//    tangent is taken toward the row above: n = tx × tUp then has +z toward
//    the camera for a surface facing it.
#include "cpu/normals.h"

#include <cmath>
#include <vector>

#include "cpu/filter_util.h"

namespace meniscus::cpu {

namespace {

// Tangent along one image axis from the point p (depth z) and its two
// neighbours (pm: previous, pp: next; zm, zp their depths, +inf when outside
// the image or no fluid). Returns false when neither neighbour is usable.
inline bool axisTangent(const glm::vec3& p, float z, const glm::vec3& pm, float zm, const glm::vec3& pp, float zp,
                        float jump, glm::vec3* t) {
    const float dzm = z - zm, dzp = zp - z;  // +inf - finite = +inf: never usable
    const bool okm = std::fabs(dzm) <= jump, okp = std::fabs(dzp) <= jump;
    if (okm && okp) {
        if (std::fabs(dzp - dzm) <= jump) {
            *t = pp - pm;  // smooth surface: central difference
            return true;
        }
        // A crease: the two sides disagree; keep the flatter one.
        *t = std::fabs(dzp) < std::fabs(dzm) ? pp - p : p - pm;
        return true;
    }
    if (okp) {
        *t = pp - p;
        return true;
    }
    if (okm) {
        *t = p - pm;
        return true;
    }
    return false;
}

}  // namespace

Image<glm::vec3> computeNormals(const Image<float>& depth, const Camera& camera, float radius, float jumpRadii) {
    const int w = depth.width, h = depth.height;
    Image<glm::vec3> out(w, h, glm::vec3(0.0f));
    if (w <= 0 || h <= 0) return out;

    // Ray components per column / row, computed exactly as Camera::pixelRay does,
    // so P(x, y) = z * (rx[x], ry[y], -1) equals camera.unproject(x+0.5, y+0.5, z).
    const float f = camera.focalPx();
    std::vector<float> rx(std::size_t(w) + 2), ry(std::size_t(h) + 2);
    for (int x = -1; x <= w; ++x) rx[std::size_t(x + 1)] = (float(x) + 0.5f - 0.5f * float(w)) / f;
    for (int y = -1; y <= h; ++y) ry[std::size_t(y + 1)] = -(float(y) + 0.5f - 0.5f * float(h)) / f;
    const float jump = jumpRadii * radius;
    constexpr float kInf = INFINITY;

    forEachRow(h, [&](int y) {
        const float* row = &depth.pixels[std::size_t(y) * std::size_t(w)];
        const float* up = y > 0 ? row - w : nullptr;
        const float* down = y + 1 < h ? row + w : nullptr;
        const float ryc = ry[std::size_t(y + 1)], ryu = ry[std::size_t(y)], ryd = ry[std::size_t(y + 2)];
        glm::vec3* dst = &out.pixels[std::size_t(y) * std::size_t(w)];
        for (int x = 0; x < w; ++x) {
            const float z = row[x];
            if (!isFluid(z)) continue;
            const float rxc = rx[std::size_t(x + 1)];
            const glm::vec3 p = z * glm::vec3(rxc, ryc, -1.0f);

            const float zl = x > 0 ? row[x - 1] : kInf, zr = x + 1 < w ? row[x + 1] : kInf;
            const float zu = up ? up[x] : kInf, zd = down ? down[x] : kInf;
            // Neighbours with infinite depth give non-finite points, but those
            // are never used: axisTangent rejects them by their depth first.
            const glm::vec3 pl = zl * glm::vec3(rx[std::size_t(x)], ryc, -1.0f);
            const glm::vec3 pr = zr * glm::vec3(rx[std::size_t(x + 2)], ryc, -1.0f);
            const glm::vec3 pu = zu * glm::vec3(rxc, ryu, -1.0f);
            const glm::vec3 pd = zd * glm::vec3(rxc, ryd, -1.0f);

            // Unit view ray, for the fallback tangents and the orientation.
            const glm::vec3 u = p / glm::length(p);
            glm::vec3 tx, tUp;  // along +x (right) and toward the row above (+y view)
            if (!axisTangent(p, z, pl, zl, pr, zr, jump, &tx)) tx = glm::vec3(1.0f, 0.0f, 0.0f) - u.x * u;
            if (!axisTangent(p, z, pd, zd, pu, zu, jump, &tUp)) tUp = glm::vec3(0.0f, 1.0f, 0.0f) - u.y * u;

            glm::vec3 n = glm::cross(tx, tUp);
            const float len = glm::length(n);
            if (!(len > 0.0f)) {
                n = -u;  // degenerate tangents: face the camera
            } else {
                n /= len;
                if (glm::dot(n, u) > 0.0f) n = -n;  // toward the eye (the surface is seen from its front)
            }
            dst[x] = n;
        }
    });
    return out;
}

}  // namespace meniscus::cpu
