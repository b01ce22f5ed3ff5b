// CPU scene stage, SPEC §3.1: the default "studio" the fluid stands in — a
// checker floor and two back walls forming the inside corner of a box around
// the particles — ray-cast per pixel into colour and eye depth, with the
// procedural sky (sky.cpp) wherever no plane is hit. Rendering the opaque scene
// first and splatting fluid against its depth is the compositing order of van
// der Laan et al. 2009 (US 8,947,430) and Instant Liquids (Cords & Staadt
// 2008, §3): fluid behind the scene is hidden and thickness stops at it.
//
// Every length comes from the particles' box and radius (checker size, wall
// margins, corner shading, distance fade), so the studio scales with the scene.
#include "cpu/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cpu/filter_util.h"

namespace meniscus::cpu {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Gap between the lowest sphere and the floor, and between the outermost
// spheres and the walls, in radii: the fluid sits just in front of the studio
// but never intersects it.
constexpr float kFloorGapRadii = 0.25f;
constexpr float kWallGapRadii = 1.0f;

// Checker square ≈ 1/8 of the box's largest horizontal extent, rounded to a
// "nice" 1, 2 or 5 times a power of ten (a readable scale in the picture).
float niceChecker(float extentM) {
    const float raw = extentM / 8.0f;
    const float decade = std::pow(10.0f, std::floor(std::log10(raw)));
    const float m = raw / decade;  // in [1, 10)
    const float nice = m < 1.5f ? 1.0f : m < 3.5f ? 2.0f : m < 7.5f ? 5.0f : 10.0f;
    return nice * decade;
}

// floor(v) as an int; v is clamped first so far-away hits cannot overflow.
int floorInt(float v) {
    v = std::clamp(v, -1.0e6f, 1.0e6f);
    const int i = int(v);
    return i - (float(i) > v ? 1 : 0);
}

// Ambient-occlusion-like darkening toward a corner edge at distance d (0 at the edge).
float cornerFall(float d, float scale) {
    const float u = std::max(0.0f, 1.0f - d / scale);
    return u * u;
}

}  // namespace

Studio makeStudio(const Bounds& particleBox, float radius, const Camera& camera, const SceneParams& params) {
    Studio s;
    s.enabled = params.background;
    Bounds box = params.studioBounds.empty() ? particleBox : params.studioBounds;
    if (box.empty()) box.extend(camera.target);  // no particles: a corner around the target
    const float r = (radius > 0.0f && std::isfinite(radius)) ? radius
                                                             : 0.01f * glm::length(camera.eye - camera.target);
    s.floorY = box.min.y - r - kFloorGapRadii * r;
    // Each wall on the far side of the box from the eye, so it stands behind the fluid.
    const glm::vec3 c = box.center();
    const float wallGap = r + kWallGapRadii * r;
    s.wallXNormal = camera.eye.x >= c.x ? 1.0f : -1.0f;
    s.wallX = s.wallXNormal > 0.0f ? box.min.x - wallGap : box.max.x + wallGap;
    s.wallZNormal = camera.eye.z >= c.z ? 1.0f : -1.0f;
    s.wallZ = s.wallZNormal > 0.0f ? box.min.z - wallGap : box.max.z + wallGap;
    const glm::vec3 e = box.extent();
    const float horizontal = std::max(e.x, e.z) + 2.0f * wallGap;
    s.checkerM = niceChecker(horizontal);
    // Walls 1.5 times the fluid's height or half the floor's size, whichever is
    // taller, ending on a whole square: a backdrop, with sky above.
    const float height = std::max(1.5f * (box.max.y + r - s.floorY), 0.5f * horizontal);
    s.wallTopY = s.floorY + std::ceil(height / s.checkerM) * s.checkerM;
    return s;
}

SceneLayer castScene(const Camera& camera, const Studio& studio) {
    const int W = camera.width, H = camera.height;
    SceneLayer out{Image<glm::vec4>(W, H, glm::vec4(0.0f)), Image<float>(W, H, kInf)};
    if (!studio.enabled) return out;

    // World ray D = dirToWorld(view ray with z = -1): eye + t D has eye depth t.
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back();
    const glm::vec3 eye = camera.eye;
    const float invF = 1.0f / camera.focalPx();
    const float halfW = 0.5f * float(W), halfH = 0.5f * float(H);
    const float nearM = camera.nearM;

    // Lighting is constant per plane (flat, one directional key light plus a
    // sky-like ambient term), so it is computed once here.
    const glm::vec3 light = ShadingParams{}.lightDirWorld;
    const float ambient = 0.45f, key = 0.55f;
    const float litFloor = ambient + key * std::max(0.0f, light.y);
    const float litWallX = ambient + key * std::max(0.0f, studio.wallXNormal * light.x);
    const float litWallZ = ambient + key * std::max(0.0f, studio.wallZNormal * light.z);
    const glm::vec3 floorLight(0.72f), floorDark(0.40f);                                // grey floor
    const glm::vec3 wallLight(0.62f, 0.64f, 0.68f), wallDark(0.44f, 0.46f, 0.50f);      // cooler walls
    const float invChecker = 1.0f / studio.checkerM;
    const float aoScale = studio.checkerM;  // corner darkening reaches about one square
    // The infinite planes fade into the sky's own colour far away (between 24
    // and 80 squares from the corner), hiding the checker's aliasing there.
    const float fadeStart = 24.0f * studio.checkerM, fadeEnd = 80.0f * studio.checkerM;

    forEachRow(H, [&](int y) {
        const float vy = -(float(y) + 0.5f - halfH) * invF;
        for (int x = 0; x < W; ++x) {
            const float vx = (float(x) + 0.5f - halfW) * invF;
            const glm::vec3 D = vx * right + vy * up - back;

            // Nearest front-facing hit among the three planes; each counts only
            // inside the corner (walls above the floor, floor and walls on the
            // camera's side of the other walls, walls below their top).
            float best = kInf;
            int plane = -1;  // 0 floor, 1 wall x, 2 wall z
            glm::vec3 p(0.0f);
            if (D.y < 0.0f) {
                const float t = (studio.floorY - eye.y) / D.y;
                const glm::vec3 q = eye + t * D;
                if (t >= nearM && (q.x - studio.wallX) * studio.wallXNormal >= 0.0f &&
                    (q.z - studio.wallZ) * studio.wallZNormal >= 0.0f) {
                    best = t, plane = 0, p = q;
                }
            }
            if (D.x * studio.wallXNormal < 0.0f) {
                const float t = (studio.wallX - eye.x) / D.x;
                const glm::vec3 q = eye + t * D;
                if (t >= nearM && t < best && q.y >= studio.floorY && q.y <= studio.wallTopY &&
                    (q.z - studio.wallZ) * studio.wallZNormal >= 0.0f)
                    best = t, plane = 1, p = q;
            }
            if (D.z * studio.wallZNormal < 0.0f) {
                const float t = (studio.wallZ - eye.z) / D.z;
                const glm::vec3 q = eye + t * D;
                if (t >= nearM && t < best && q.y >= studio.floorY && q.y <= studio.wallTopY &&
                    (q.x - studio.wallX) * studio.wallXNormal >= 0.0f)
                    best = t, plane = 2, p = q;
            }

            if (plane < 0) {
                out.color.at(x, y) = glm::vec4(skyColor(D), 1.0f);
                continue;
            }
            // Plane coordinates measured from the corner edges, so the squares
            // line up across the corner; (a, b) = distances to the two other planes.
            const float dx = (p.x - studio.wallX) * studio.wallXNormal;
            const float dz = (p.z - studio.wallZ) * studio.wallZNormal;
            const float dy = p.y - studio.floorY;
            float a, b, lit;
            if (plane == 0) a = dx, b = dz, lit = litFloor;
            else if (plane == 1) a = dz, b = dy, lit = litWallX;
            else a = dx, b = dy, lit = litWallZ;
            const bool odd = ((floorInt(a * invChecker) + floorInt(b * invChecker)) & 1) != 0;
            const glm::vec3 albedo = plane == 0 ? (odd ? floorDark : floorLight) : (odd ? wallDark : wallLight);
            const float ao = 1.0f - 0.25f * (cornerFall(a, aoScale) + cornerFall(b, aoScale));
            glm::vec3 c = albedo * (lit * ao);
            const float far = std::max(a, b);
            if (far > fadeStart) c = glm::mix(c, skyColor(D), std::min(1.0f, (far - fadeStart) / (fadeEnd - fadeStart)));
            out.color.at(x, y) = glm::vec4(c, 1.0f);
            out.depth.at(x, y) = best;
        }
    });
    return out;
}

}  // namespace meniscus::cpu
