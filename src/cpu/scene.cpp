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
    if (!(raw > 0.0f) || !std::isfinite(raw)) return 1.0f;  // degenerate box: any size will do
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

namespace {

// Everything one pixel of castScene needs, by value: a row works on its own
// copy, so no load in the loop can alias the output (the compiler then
// if-converts and vectorises the plane pass).
struct CastConstants {
    glm::vec3 eye, right, up, back;
    float invF, halfW, halfH, nearM;
    float floorY, wallX, wallZ, nX, nZ, topY;
    float invChecker, aoScale, fadeStart, invFade;
    float litFloor, litWallX, litWallZ;
    float floorLight[3], floorDark[3], wallLight[3], wallDark[3];  // linear RGB
};

void castRow(const CastConstants c, int y, int width, float* depthRow, glm::vec4* colourRow) {
    // World ray D = dirToWorld(view ray with z = -1): eye + t D has eye depth t.
    const glm::vec3 rowDir = (-(float(y) + 0.5f - c.halfH) * c.invF) * c.up - c.back;
    // In chunks: a branch-free pass for the planes, then a scalar pass for the
    // few pixels that need the sky (no hit, or the far fade).
    constexpr int kChunk = 64;
    float red[kChunk], green[kChunk], blue[kChunk], fade[kChunk];
    for (int x0 = 0; x0 < width; x0 += kChunk) {
        const int n = std::min(kChunk, width - x0);
        for (int k = 0; k < n; ++k) {
            const float vx = (float(x0 + k) + 0.5f - c.halfW) * c.invF;
            const float Dx = rowDir.x + vx * c.right.x, Dy = rowDir.y + vx * c.right.y, Dz = rowDir.z + vx * c.right.z;
            // Each plane counts only where hit from its front, beyond the near
            // plane and inside the corner (walls above the floor and below their
            // top, everything on the camera's side of the walls).
            const float tF = (c.floorY - c.eye.y) / Dy;
            const bool okF = Dy < 0.0f && tF >= c.nearM && (c.eye.x + tF * Dx - c.wallX) * c.nX >= 0.0f &&
                             (c.eye.z + tF * Dz - c.wallZ) * c.nZ >= 0.0f;
            const float tX = (c.wallX - c.eye.x) / Dx;
            const float yX = c.eye.y + tX * Dy;
            const bool okX = Dx * c.nX < 0.0f && tX >= c.nearM && yX >= c.floorY && yX <= c.topY &&
                             (c.eye.z + tX * Dz - c.wallZ) * c.nZ >= 0.0f;
            const float tZ = (c.wallZ - c.eye.z) / Dz;
            const float yZ = c.eye.y + tZ * Dy;
            const bool okZ = Dz * c.nZ < 0.0f && tZ >= c.nearM && yZ >= c.floorY && yZ <= c.topY &&
                             (c.eye.x + tZ * Dx - c.wallX) * c.nX >= 0.0f;
            // The nearest valid hit (in exact arithmetic at most one is valid).
            float t = okF ? tF : kInf;
            int plane = okF ? 0 : -1;
            plane = okX && tX < t ? 1 : plane;
            t = okX && tX < t ? tX : t;
            plane = okZ && tZ < t ? 2 : plane;
            t = okZ && tZ < t ? tZ : t;
            const float tt = plane >= 0 ? t : 0.0f;  // keeps the arithmetic below finite
            // Plane coordinates from the corner edges, so the squares line up
            // across the corner; (a, b) are also the distances to the two other planes.
            const float dx = (c.eye.x + tt * Dx - c.wallX) * c.nX;
            const float dy = c.eye.y + tt * Dy - c.floorY;
            const float dz = (c.eye.z + tt * Dz - c.wallZ) * c.nZ;
            const float a = plane == 1 ? dz : dx;
            const float b = plane == 0 ? dz : dy;
            const bool odd = ((floorInt(a * c.invChecker) + floorInt(b * c.invChecker)) & 1) != 0;
            const bool onFloor = plane == 0;
            // Per channel (a select of whole vectors would become a load through a chosen address).
            auto pick = [&](int ch) {
                return odd ? (onFloor ? c.floorDark[ch] : c.wallDark[ch]) : (onFloor ? c.floorLight[ch] : c.wallLight[ch]);
            };
            const float lit = onFloor ? c.litFloor : plane == 1 ? c.litWallX : c.litWallZ;
            const float ao = 1.0f - 0.25f * (cornerFall(a, c.aoScale) + cornerFall(b, c.aoScale));
            const float shade = lit * ao;
            red[k] = pick(0) * shade;
            green[k] = pick(1) * shade;
            blue[k] = pick(2) * shade;
            // The weight of the sky: -1 where no plane is hit.
            fade[k] = plane >= 0 ? std::clamp((std::max(a, b) - c.fadeStart) * c.invFade, 0.0f, 1.0f) : -1.0f;
            depthRow[x0 + k] = t;
        }
        for (int k = 0; k < n; ++k) {
            glm::vec3 rgb(red[k], green[k], blue[k]);
            if (fade[k] != 0.0f) {
                const float vx = (float(x0 + k) + 0.5f - c.halfW) * c.invF;
                const glm::vec3 sky = skyColor(rowDir + vx * c.right);
                rgb = fade[k] < 0.0f ? sky : glm::mix(rgb, sky, fade[k]);
            }
            colourRow[x0 + k] = glm::vec4(rgb, 1.0f);
        }
    }
}

}  // namespace

SceneLayer castScene(const Camera& camera, const Studio& studio) {
    const int W = camera.width, H = camera.height;
    SceneLayer out{Image<glm::vec4>(W, H, glm::vec4(0.0f)), Image<float>(W, H, kInf)};
    if (!studio.enabled) return out;

    CastConstants c;
    c.eye = camera.eye;
    c.right = camera.right();
    c.up = camera.trueUp();
    c.back = camera.back();
    c.invF = 1.0f / camera.focalPx();
    c.halfW = 0.5f * float(W);
    c.halfH = 0.5f * float(H);
    c.nearM = camera.nearM;
    c.floorY = studio.floorY;
    c.wallX = studio.wallX;
    c.wallZ = studio.wallZ;
    c.nX = studio.wallXNormal;
    c.nZ = studio.wallZNormal;
    c.topY = studio.wallTopY;
    c.invChecker = 1.0f / studio.checkerM;
    c.aoScale = studio.checkerM;  // corner darkening reaches about one square
    // The infinite floor fades into the sky's own colour far away (between 24
    // and 80 squares from the corner), hiding the checker's aliasing there.
    c.fadeStart = 24.0f * studio.checkerM;
    c.invFade = 1.0f / (56.0f * studio.checkerM);
    // Lighting is constant per plane (flat, one directional key light plus a
    // sky-like ambient term), so it is computed once here.
    const glm::vec3 light = ShadingParams{}.lightDirWorld;
    const float ambient = 0.45f, key = 0.55f;
    c.litFloor = ambient + key * std::max(0.0f, light.y);
    c.litWallX = ambient + key * std::max(0.0f, studio.wallXNormal * light.x);
    c.litWallZ = ambient + key * std::max(0.0f, studio.wallZNormal * light.z);
    const float floorLight[3] = {0.72f, 0.72f, 0.72f}, floorDark[3] = {0.40f, 0.40f, 0.40f};  // grey floor
    const float wallLight[3] = {0.62f, 0.64f, 0.68f}, wallDark[3] = {0.44f, 0.46f, 0.50f};      // cooler walls
    std::copy_n(floorLight, 3, c.floorLight);
    std::copy_n(floorDark, 3, c.floorDark);
    std::copy_n(wallLight, 3, c.wallLight);
    std::copy_n(wallDark, 3, c.wallDark);

    forEachRow(H, [&](int y) { castRow(c, y, W, &out.depth.at(0, y), &out.color.at(0, y)); });
    return out;
}

}  // namespace meniscus::cpu
