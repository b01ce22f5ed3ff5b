// CPU scene stage, docs/pipeline.md#scene: the default "studio" the fluid stands in — a
// checker floor and two back walls forming the inside corner of a box around
// the particles, or the floor alone for a moving camera — ray-cast per pixel into colour and eye depth, with the
// procedural sky (sky.cpp), or the HDR environment map (shared/environment.h),
// wherever no plane is hit. Rendering the opaque scene
// first and splatting fluid against its depth is the compositing order of van
// der Laan et al. 2009 (US 8,947,430) and Instant Liquids (Cords & Staadt
// 2008, §3): fluid behind the scene is hidden and thickness stops at it.
//
// The studio itself (shared::makeStudio), its colours, lighting and per-pixel
// formulas (src/shared/studio_shade.h) are shared with the GL twin.
#include "cpu/scene.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cpu/filter_util.h"
#include "cpu/sky.h"
#include "shared/environment.h"
#include "shared/studio_shade.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

namespace {

using shared::studioCornerFall;
using shared::studioFloorInt;
using shared::studioFloorRadius;

// Everything one pixel of castScene needs, by value: a row works on its own
// copy, so no load in the loop can alias the output (the compiler then
// if-converts and vectorises the plane pass).
struct CastConstants {
    glm::vec3 eye, right, up, back;
    float invF, halfW, halfH, nearM;
    float floorY, wallX, wallZ, nX, nZ, topY;
    shared::StudioShading sh;  // checker, corner, fade, per-plane lighting, sun
    float floorLight[3], floorDark[3], wallLight[3], wallDark[3];  // linear RGB
    shared::EnvironmentMap env;  // the HDR map in place of the sky (disabled: the procedural sky)
};

// Walls = false: the floor alone, (a, b) its coordinates from the box's centre
// (c.wallX, c.wallZ with normals +1), no corner darkening, a radial far fade.
// A template parameter, so the studio with walls compiles as it always did.
template <bool Walls>
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
            const bool okF = Dy < 0.0f && tF >= c.nearM &&
                             (!Walls || ((c.eye.x + tF * Dx - c.wallX) * c.nX >= 0.0f &&
                                         (c.eye.z + tF * Dz - c.wallZ) * c.nZ >= 0.0f));
            const float tX = (c.wallX - c.eye.x) / Dx;
            const float yX = c.eye.y + tX * Dy;
            const bool okX = Walls && Dx * c.nX < 0.0f && tX >= c.nearM && yX >= c.floorY && yX <= c.topY &&
                             (c.eye.z + tX * Dz - c.wallZ) * c.nZ >= 0.0f;
            const float tZ = (c.wallZ - c.eye.z) / Dz;
            const float yZ = c.eye.y + tZ * Dy;
            const bool okZ = Walls && Dz * c.nZ < 0.0f && tZ >= c.nearM && yZ >= c.floorY && yZ <= c.topY &&
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
            const bool odd = ((studioFloorInt(a * c.sh.invChecker) + studioFloorInt(b * c.sh.invChecker)) & 1) != 0;
            const bool onFloor = plane == 0;
            // Per channel (a select of whole vectors would become a load through a chosen address).
            auto pick = [&](int ch) {
                return odd ? (onFloor ? c.floorDark[ch] : c.wallDark[ch])
                           : (onFloor ? c.floorLight[ch] : c.wallLight[ch]);
            };
            auto lit = [&](int ch) {
                return onFloor ? c.sh.litFloor[ch] : plane == 1 ? c.sh.litWallX[ch] : c.sh.litWallZ[ch];
            };
            const float ao =
                Walls ? 1.0f - 0.25f * (studioCornerFall(a, c.sh.aoScale) + studioCornerFall(b, c.sh.aoScale)) : 1.0f;
            red[k] = pick(0) * (lit(0) * ao);
            green[k] = pick(1) * (lit(1) * ao);
            blue[k] = pick(2) * (lit(2) * ao);
            // The weight of the sky: -1 where no plane is hit.
            const float reach = Walls ? std::max(a, b) : studioFloorRadius(a, b);
            fade[k] = plane >= 0 ? std::clamp((reach - c.sh.fadeStart) * c.sh.invFade, 0.0f, 1.0f) : -1.0f;
            depthRow[x0 + k] = t;
        }
        for (int k = 0; k < n; ++k) {
            glm::vec3 rgb(red[k], green[k], blue[k]);
            if (fade[k] != 0.0f) {
                const float vx = (float(x0 + k) + 0.5f - c.halfW) * c.invF;
                const glm::vec3 dir = rowDir + vx * c.right;
                const glm::vec3 sky = c.env.enabled() ? shared::environmentMapRadiance(dir.x, dir.y, dir.z, c.env)
                                                      : skyColor(dir, c.sh.sunDir);
                rgb = fade[k] < 0.0f ? sky : glm::mix(rgb, sky, fade[k]);
            }
            colourRow[x0 + k] = glm::vec4(rgb, 1.0f);
        }
    }
}

}  // namespace

SceneLayer castScene(const Camera& camera, const shared::Studio& studio, const shared::EnvironmentMap& environment) {
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
    c.sh = shared::studioShading(studio, environment);
    c.env = environment;
    for (int ch = 0; ch < 3; ++ch) {
        c.floorLight[ch] = shared::kStudioFloorLight[ch];
        c.floorDark[ch] = shared::kStudioFloorDark[ch];
        c.wallLight[ch] = shared::kStudioWallLight[ch];
        c.wallDark[ch] = shared::kStudioWallDark[ch];
    }

    if (studio.walls) forEachRow(H, [&](int y) { castRow<true>(c, y, W, &out.depth.at(0, y), &out.color.at(0, y)); });
    else forEachRow(H, [&](int y) { castRow<false>(c, y, W, &out.depth.at(0, y), &out.color.at(0, y)); });
    return out;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runScene(Backend& b, const StageIo& io) { CpuBackend::of(b).castScene(io.at.sceneColor, io.at.sceneDepth); }

}  // namespace

extern const StageDriver kSceneStage = {nullptr, runScene};

}  // namespace meniscus::cpu
