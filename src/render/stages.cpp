// The stage list (stages.h): each stage's declaration and the check of its
// parameters, said here once; runStages in pipeline.cpp runs them in this order.
#include "render/stages.h"

#include <string>

#include "core/fluid_scale.h"

namespace meniscus {

bool drawsDrops(const RenderSettings& s) { return s.spray.enabled || !s.diffuse.empty(); }

namespace {

// "RenderSettings::<what>.<bad>" when a params check returned `bad`.
Status settingError(const char* what, const std::string& bad) {
    if (bad.empty()) return okStatus();
    return makeError("", std::string("RenderSettings::") + what + bad);
}

bool always(const RenderSettings&) { return true; }
bool reduced(const RenderSettings& s) { return s.fluidScale != 1.0f; }
bool screenPath(const RenderSettings& s) { return !s.mesh && !s.raycast.enabled; }
bool sortLast(const RenderSettings& s) { return s.compositor != nullptr; }

Status checkReduced(const RenderSettings& s) {
    const int divisor = fluidDivisor(s.fluidScale);
    if (divisor == 0)
        return makeError("", "RenderSettings::fluidScale: expected 1, 0.5 or 0.25, got " + std::to_string(s.fluidScale));
    if (divisor > 1 && s.mesh)
        return makeError("", "RenderSettings::fluidScale: reduced resolution is for the particle surface, not the mesh path");
    return okStatus();
}

Status checkSplat(const RenderSettings& s) {  // the thickness, and the hole filling read with it
    return settingError("", checkHoleFillParams(s.holeFill, s.thickness));
}

Status checkRaycast(const RenderSettings& s) {
    if (!s.raycast.enabled) return okStatus();
    if (auto st = settingError("raycast.", checkRaycastParams(s.raycast)); !st) return st;
    if (s.mesh) return makeError("", "RenderSettings::raycast: the ray cast is for the particle surface, not the mesh path");
    return okStatus();
}

Status checkNoise(const RenderSettings& s) {
    if ((s.view == View::Noise || s.view == View::Foam) && !s.noise.enabled)
        return makeError("", "the noise and foam views need the surface noise on (RenderSettings::noise.enabled)");
    if (!s.noise.enabled) return okStatus();
    return settingError("noise.", checkNoiseParams(s.noise));
}

Status checkWhitening(const RenderSettings& s) {
    if (s.view == View::Whitening && !s.whitening.enabled)
        return makeError("", "the whitening view needs the velocity whitening on (RenderSettings::whitening.enabled)");
    if (!s.whitening.enabled) return okStatus();
    return settingError("whitening.", checkWhiteningParams(s.whitening));
}

Status checkSilhouette(const RenderSettings& s) {
    if (s.view == View::Silhouette && !s.silhouette.enabled)
        return makeError("", "the silhouette view needs the silhouette reduction on (RenderSettings::silhouette.enabled)");
    if (!s.silhouette.enabled) return okStatus();
    return settingError("silhouette.", checkSilhouetteParams(s.silhouette));
}

Status checkSpray(const RenderSettings& s) {
    const bool drops = drawsDrops(s);
    if (s.view == View::Spray && !drops)
        return makeError("", "the spray view needs the spray on (RenderSettings::spray.enabled) or a diffuse layer");
    if (!s.diffuse.velocities.empty() && s.diffuse.velocities.size() != s.diffuse.positions.size())
        return makeError("", "RenderSettings::diffuse: velocities must be empty or one per position");
    if (!s.diffuse.kind.empty() && s.diffuse.kind.size() != s.diffuse.positions.size())
        return makeError("", "RenderSettings::diffuse: kind must be empty or one per position");
    if (!drops) return okStatus();
    return settingError("spray.", checkSprayParams(s.spray));
}

Status checkAnisotropy(const RenderSettings& s) {
    if (!s.anisotropy.enabled) return okStatus();
    return settingError("anisotropy.", checkAnisotropyParams(s.anisotropy));
}

// The list. A check sees the settings whether or not its stage runs (a view
// may ask for a stage that is off: the check says which setting to turn on).
const StageDecl kStages[] = {
    // Host work, before the images: the spray's split, the ray cast's field, the kernels.
    {"spray-classify", "particles (density, velocity)", "the body's particles, the drops", drawsDrops, checkSpray},
    {"sph-field", "particles", "the SPH density grid of the ray cast", [](const RenderSettings& s) { return s.raycast.enabled; },
     checkRaycast},
    {"anisotropy", "particles", "one ellipsoid and centre per particle",
     [](const RenderSettings& s) { return s.anisotropy.enabled; }, checkAnisotropy},
    // The images.
    {"scene", "camera, studio, light", "SceneColor, SceneDepth", always, nullptr},
    {"reduce-scene-depth", "SceneDepth", "LowSceneDepth", reduced, checkReduced},
    {"depth-splat+thickness", "SceneDepth, particles", "RawDepth, Thickness", always, checkSplat},
    // The same over several processes (RenderSettings::compositor): this share's splat, the
    // exact combination of every share's, the thickness resolved from it on the root.
    {"depth-splat", "SceneDepth, this share's particles", "the partial", sortLast, nullptr},
    {"composite", "every process's partial", "the combined partial", sortLast, nullptr},
    {"thickness", "the combined partial", "RawDepth, Thickness", sortLast, nullptr},
    {"fill-holes", "SceneDepth, RawDepth, Thickness", "RawDepth, Thickness",
     [](const RenderSettings& s) { return screenPath(s) && s.holeFill.enabled; }, nullptr},
    {"smooth", "RawDepth", "Depth", screenPath, nullptr},
    {"normals", "Depth", "Normal", screenPath, nullptr},
    {"rasterise", "SceneDepth, the mesh", "Depth, Normal", [](const RenderSettings& s) { return s.mesh != nullptr; },
     nullptr},
    {"raycast", "SceneDepth, RawDepth, the field", "Depth, Normal",
     [](const RenderSettings& s) { return s.raycast.enabled; }, nullptr},
    {"noise", "Depth, Normal, particles (id, velocity)", "Noise, Normal",
     [](const RenderSettings& s) { return s.noise.enabled; }, checkNoise},
    {"upsample", "the Low images, SceneDepth", "Depth, Normal, Thickness, Noise, Coverage", reduced, nullptr},
    {"whitening", "Depth, particles (velocity)", "Whitening", [](const RenderSettings& s) { return s.whitening.enabled; },
     checkWhitening},
    {"shade", "SceneColor, SceneDepth, Depth, Normal, Thickness, Noise, Whitening", "Color", always, nullptr},
    {"fluid-edges", "SceneColor, Depth, Coverage, Color", "Color", reduced, nullptr},
    // With several fluids in the particles (runs: may run; the particles decide).
    {"composite-fluids", "each fluid's layer", "Color, Depth, Normal, Thickness, FluidId", always, nullptr},
    {"silhouette", "SceneColor, Depth, Color", "Color, Silhouette", [](const RenderSettings& s) { return s.silhouette.enabled; },
     checkSilhouette},
    {"spray", "SceneDepth, Depth, Color, the drops", "Color, Spray", drawsDrops, nullptr},
    // After the stages, render() reads the images it returns back to the host.
    {"readback", "Color and the AOVs", "the host's Aovs", always, nullptr},
};

}  // namespace

std::span<const StageDecl> frameStages() { return kStages; }

Status checkStages(const RenderSettings& s) {
    for (const StageDecl& stage : kStages)
        if (stage.check)
            if (auto st = stage.check(s); !st) return st;
    return okStatus();
}

}  // namespace meniscus
