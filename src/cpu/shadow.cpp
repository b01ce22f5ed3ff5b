// CPU shadow stages (docs/geometry.md#shadows). shadow-map: on the key
// light's camera (core/shadow_camera.h) the geometry's nearest depth (a
// shadow map, Williams 1978, "Casting curved shadows on curved surfaces")
// and the liquid's nearest depth and thickness (the depth-splat+thickness
// driver, with the light's depth as its scene depth). shadows: each scene
// pixel's point looked up in those maps (the nearest texel): behind the
// geometry it loses the key light, behind the liquid the key light is
// attenuated by Beer-Lambert's law, exp(-k T) per channel for the thickness
// T the light crosses. The per-pixel formulas are src/shared/shadow.h, the
// GL twin's (src/gl/shadow.cpp) too.
#include "cpu/cpu_backend.h"

#include <limits>

#include "core/shadow_camera.h"
#include "cpu/filter_util.h"
#include "cpu/raster_mesh.h"
#include "shared/environment.h"
#include "shared/shadow.h"
#include "shared/sky.h"
#include "shared/studio_shade.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

extern const StageDriver kSplatStage;

namespace {


// On the light's camera (the stage's row switched to it): io.at.sceneDepth
// the geometry's depth, io.at.raw and io.at.thickness the liquid's.
void runShadowMap(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    // The geometry's part depends on the geometry and the light's camera
    // only: drawn once while they stay (CpuBackend::casterDepth).
    c.scalarOut(io.at.sceneDepth) = c.casterDepth([&](Image<float>& depth) {
        TriangleMesh casters;
        shadowCasters(s.geometry.get(), s.camera.eye, casters);
        if (casters.empty()) return;
        MeshRaster r;
        rasteriseMesh(s.camera, casters, nullptr, r);
        depth = std::move(r.depth);
    });
    kSplatStage.run(b, io);
}

void runShadows(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    const ShadowLight& light = s.shadow;
    const Camera& lc = light.camera;
    const Image<float>& lightDepth = c.scalar(Slot::LightDepth);
    const Image<float>& lightRaw = c.scalar(Slot::LightRaw);
    const Image<float>& lightThickness = c.scalar(Slot::LightThickness);
    const int side = shared::kShadowMapPx;
    if (lightDepth.width != side || lightDepth.height != side) return;  // no map (a stage run alone)
    const Image<float>& depth = c.scalar(io.at.sceneDepth);
    Image<glm::vec4>& color = c.colorToPaint(io.at.sceneColor);
    const Camera& cam = s.camera;
    const int W = cam.width, H = cam.height;
    if (depth.width != W || depth.height != H || color.width != W || color.height != H) return;
    const glm::vec3 right = cam.right(), up = cam.trueUp(), back = cam.back(), eye = cam.eye;
    const glm::vec3 lRight = lc.right(), lUp = lc.trueUp(), lBack = lc.back(), lEye = lc.eye;
    const float invF = 1.0f / cam.focalPx(), lf = lc.focalPx();
    const glm::vec3 L = shared::sunDirection(s.studio.lightDirWorld);
    const glm::vec3 k = s.shading.material.absorptionPerM;
    forEachRow(H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            const float z = depth.at(x, y);
            if (!(z < 3.0e38f)) continue;
            const float zl = x > 0 ? depth.at(x - 1, y) : kInf, zr = x + 1 < W ? depth.at(x + 1, y) : kInf;
            const float zu = y > 0 ? depth.at(x, y - 1) : kInf, zd = y + 1 < H ? depth.at(x, y + 1) : kInf;
            glm::vec3 pv, nv;
            if (!shared::shadowSurface(x, y, z, zl, zr, zu, zd, invF, W, H, pv, nv)) continue;
            const glm::vec3 p = eye + pv.x * right + pv.y * up + pv.z * back;
            const glm::vec3 n = nv.x * right + nv.y * up + nv.z * back;
            const float nl = n.x * L.x + n.y * L.y + n.z * L.z;
            if (!(nl > 0.0f)) continue;  // the key light does not reach it anyway
            float dp = 0.0f;
            const glm::ivec3 t = shared::shadowTexel(p, lEye, lRight, lUp, lBack, lf, side, dp);
            if (t.z == 0) continue;
            const float bias = shared::shadowBias(nl, light.texelM);
            glm::vec3 lit(1.0f);
            if (dp > lightDepth.at(t.x, t.y) + bias) lit = glm::vec3(0.0f);
            else if (lightRaw.at(t.x, t.y) < dp - bias)
                lit = shared::liquidTransmittance(k, lightThickness.at(t.x, t.y));
            glm::vec4& out = color.at(x, y);
            // With an HDR map the ambient is its irradiance E(n) / pi at the normal.
            const glm::vec3 rgb =
                s.environment.enabled()
                    ? shared::shadowedColorRgb(glm::vec3(out), shared::environmentAmbient(n.x, n.y, n.z, s.environment),
                                               shared::kStudioKey, nl, lit)
                    : shared::shadowedColor(glm::vec3(out), shared::kStudioAmbient, shared::kStudioKey, nl, lit);
            out = glm::vec4(rgb, out.a);
        }
    });
}

}  // namespace

extern const StageDriver kShadowMapStage = {nullptr, runShadowMap};
extern const StageDriver kShadowsStage = {nullptr, runShadows};

}  // namespace meniscus::cpu
