// The SPH surface, ray cast (docs/pipeline.md#ray-cast-surface; RaycastParams
// in params.h): per covered pixel, shared::sphRaycast over evaluateSphField
// from the splat's depth. The GL twin is shaders/raycast.comp.
#include "cpu/raycast.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cmath>

#include "cpu/filter_util.h"
#include "shared/sph_surface.h"

namespace meniscus::cpu {

RaycastImages raycastSurface(const Camera& camera, const SphField& field, const RaycastParams& params, float radius,
                             const Image<float>& startDepth, const Image<float>* sceneDepth) {
    const int W = startDepth.width, H = startDepth.height;
    RaycastImages out{Image<float>(W, H, INFINITY), Image<glm::vec3>(W, H, glm::vec3(0.0f))};
    if (field.grid.points().empty()) return out;  // no particles: no surface
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back(), eye = camera.eye;
    const float f = camera.focalPx(), halfW = 0.5f * float(W), halfH = 0.5f * float(H);
    const float step = params.stepRadii * radius;
    const float invH2 = 1.0f / (field.support * field.support);
    const bool scene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    const SphFieldOnGrid fieldAt{field};
    forEachRow(H, [&](int y) {
        const float ry = -((float(y) + 0.5f) - halfH) / f;
        for (int x = 0; x < W; ++x) {
            const std::size_t k = std::size_t(y) * W + x;
            const float t0 = startDepth.pixels[k];
            if (!isFluid(t0)) continue;
            const float rx = ((float(x) + 0.5f) - halfW) / f;
            const glm::vec3 dir = shared::sphRayDir(rx, ry, right, up, back);
            const float tMax = scene ? std::min(sceneDepth->pixels[k], camera.farM) : camera.farM;
            glm::vec3 grad(0.0f);
            const float t = shared::sphRaycast(eye, dir, t0, camera.nearM, tMax, step, params.maxSteps,
                                               params.newtonSteps, field.isoRaw, invH2, grad, fieldAt);
            if (!isFluid(t)) continue;
            out.depth.pixels[k] = t;
            out.normal.pixels[k] = shared::sphNormalView(grad, right, up, back);
        }
    });
    return out;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runRaycast(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    static const SphField kNoField;  // no field: no surface
    auto r = raycastSurface(s.camera, s.field ? *s.field : kNoField, s.raycast, s.radius, c.scalar(io.at.raw),
                            &c.scalar(io.at.sceneDepth));
    c.scalarOut(io.at.depth) = std::move(r.depth);
    c.vec3(io.at.normal) = std::move(r.normal);
}

}  // namespace

extern const StageDriver kRaycastStage = {nullptr, runRaycast};

}  // namespace meniscus::cpu
