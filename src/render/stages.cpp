// The stage list (stages.h): each stage's declaration, the check of its
// parameters and its call, said here once; runStages in pipeline.cpp runs
// each scope through runScope, so the order is this list's.
#include "render/stages.h"

#include <string>

#include "core/fluid_scale.h"
#include "core/geometry_draw.h"
#include "core/shadow_camera.h"
#include "shared/thickness.h"

namespace meniscus {

bool drawsDrops(const RenderSettings& s) { return s.spray.enabled || !s.diffuse.empty(); }

// The stages' drivers, each defined in its stage's own file.
#define MENISCUS_STAGE_DRIVERS(X)                                                                          \
    X(kSceneStage) X(kGeometryStage) X(kReduceSceneDepthStage) X(kSplatStage) X(kSplatPartialStage) X(kResolveSplatStage)     \
    X(kFillHolesStage) X(kSmoothStage) X(kNormalsStage) X(kRasteriseStage) X(kRaycastStage) X(kNoiseStage) \
    X(kUpsampleStage) X(kWhiteningStage) X(kShadeStage) X(kFluidEdgesStage) X(kCompositeFluidsStage)        \
    X(kSilhouetteStage) X(kSprayStage) X(kGlassStage) X(kShadowMapStage) X(kShadowsStage)
#define MENISCUS_DECLARE_DRIVER(name) extern const StageDriver name;
namespace cpu {
MENISCUS_STAGE_DRIVERS(MENISCUS_DECLARE_DRIVER)
}  // namespace cpu
#if MENISCUS_HAVE_GL
namespace gl {
MENISCUS_STAGE_DRIVERS(MENISCUS_DECLARE_DRIVER)
}  // namespace gl
#define DRIVERS(name) &cpu::name, &gl::name
#else
#define DRIVERS(name) &cpu::name, nullptr  // a build without GL
#endif

namespace {

// "RenderSettings::<what>.<bad>" when a params check returned `bad`.
Status settingError(const char* what, const std::string& bad) {
    if (bad.empty()) return okStatus();
    return makeError("", std::string("RenderSettings::") + what + bad);
}

bool always(const StageWhen&) { return true; }
bool reduced(const StageWhen& w) { return w.settings.fluidScale != 1.0f; }
bool screenPath(const StageWhen& w) { return !w.settings.mesh && !w.settings.raycast.enabled; }
bool sortLast(const StageWhen& w) { return w.settings.compositor != nullptr; }

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

bool drawsGeometry(const StageWhen& w) { return drawsAnyObject(w.settings.geometry.get()); }

Status checkGeometry(const RenderSettings& s) {
    if (!s.geometry) return okStatus();
    for (std::size_t i = 0; i < s.geometry->objects.size(); ++i) {
        const GeometryObject& o = s.geometry->objects[i];
        if (auto st = o.mesh.validate(true); !st)
            return makeError("", "RenderSettings::geometry: object " + std::to_string(i) + " (" + o.name +
                                     "): " + st.error().message);
    }
    return okStatus();
}

Status checkAnisotropy(const RenderSettings& s) {
    if (!s.anisotropy.enabled) return okStatus();
    return settingError("anisotropy.", checkAnisotropyParams(s.anisotropy));
}

// ---------------------------------------------------------------- the host's side

// The scene depth at the low camera's size, reduced on the low camera.
Status runReduceSceneDepth(StageRun& r) {
    r.backend.setCamera(r.splatCamera);
    r.drive();
    r.backend.setCamera(r.settings.camera);
    return okStatus();
}

// The light's maps on the key light's camera (core/shadow_camera.h) in the
// Light* slots, then the frame's camera again (the GL frame block follows
// the camera).
Status runShadowMap(StageRun& r) {
    r.backend.setCamera(r.frame.shadow.camera);
    StageIo io = r.io;
    io.at.sceneDepth = Slot::LightDepth, io.at.raw = Slot::LightRaw, io.at.thickness = Slot::LightThickness;
    driverFor(*r.stage, r.backend)->run(r.backend, io);
    r.backend.setCamera(r.settings.camera);
    return okStatus();
}

// Every process's partial combined (exact: min and integer sums); a process
// other than the root hands its share over and its frame ends here.
Status runComposite(StageRun& r) {
    const Status composited = r.settings.compositor->composite(r.partial);
    if (!composited)
        return makeError(composited.error().file, "composite (RenderSettings::compositor): " + composited.error().message);
    if (!r.settings.compositor->root()) r.handedOver = true;
    return okStatus();
}

// On the root, the thickness resolved from the combination (weight, blur,
// upsampling on the combined depth), which is then the partial of all the
// particles. The combination has the partials' sizes; anything else
// (processes with different settings) would be read out of bounds.
Status runResolveSplat(StageRun& r) {
    const int d = shared::thicknessDivisor(r.frame.thickness.resolutionDivisor);
    const int W = r.splatCamera.width, H = r.splatCamera.height, w = (W + d - 1) / d, h = (H + d - 1) / d;
    const SplatPartial& p = r.partial;
    auto size = [](int x, int y) { return std::to_string(x) + "x" + std::to_string(y); };
    if (p.depth.width != W || p.depth.height != H || p.chords.width != w || p.chords.height != h)
        return makeError("", "composite (RenderSettings::compositor): the combined partial's depth is " +
                                 size(p.depth.width, p.depth.height) + " and its chords " +
                                 size(p.chords.width, p.chords.height) + ", expected " + size(W, H) + " and " +
                                 size(w, h) + ": every process must render with the same camera and settings");
    r.drive();
    return okStatus();
}

// ---------------------------------------------------------------- the list

// A check sees the settings whether or not its stage runs (a view may ask
// for a stage that is off: the check says which setting to turn on).
using S = StageScope;
const StageDecl kStages[] = {
    // Host work, before the images: the spray's split, the fluids, the ray cast's field, the shapes.
    {"spray-classify", S::Host, "particles (density, velocity)", "the body's particles, the drops",
     [](const StageWhen& w) { return drawsDrops(w.settings); }, checkSpray, nullptr, nullptr, nullptr,
     hostSprayClassify},
    {"fluid-split", S::Host, "the body's particles (fluid index, radius)",
     "each fluid's particles; the positions, contiguous", always, nullptr, nullptr, nullptr, nullptr, hostFluidSplit},
    {"sph-field", S::Host, "particles", "the SPH density grid of the ray cast",
     [](const StageWhen& w) { return w.settings.raycast.enabled; }, checkRaycast, nullptr, nullptr, nullptr,
     hostSphField},
    {"anisotropy", S::Host, "particles (radius)",
     "one shape per particle (and with anisotropy its smoothed centre)",
     [](const StageWhen& w) {
         const RenderSettings& s = w.settings;
         return s.anisotropy.enabled || s.raycast.enabled || s.particleRadii;
     },
     checkAnisotropy, nullptr, nullptr, nullptr, hostShapes},
    // The images: the scene, once.
    {"scene", S::Frame, "camera, studio, light", "SceneColor, SceneDepth", always, nullptr, DRIVERS(kSceneStage)},
    {"geometry", S::Frame, "SceneColor, SceneDepth, the geometry, light", "SceneColor, SceneDepth", drawsGeometry,
     checkGeometry, DRIVERS(kGeometryStage)},
    // The key light's shadows (docs/geometry.md#shadows): its maps, then the scene darkened where they hide it.
    {"shadow-map", S::Frame, "particles, the geometry, light", "LightDepth, LightRaw, LightThickness",
     [](const StageWhen& w) { return drawsShadows(w.settings); }, nullptr, DRIVERS(kShadowMapStage), runShadowMap},
    {"shadows", S::Frame, "SceneColor, SceneDepth, LightDepth, LightRaw, LightThickness", "SceneColor",
     [](const StageWhen& w) { return drawsShadows(w.settings); }, nullptr, DRIVERS(kShadowsStage)},
    {"reduce-scene-depth", S::Frame, "SceneDepth", "LowSceneDepth", reduced, checkReduced,
     DRIVERS(kReduceSceneDepthStage), runReduceSceneDepth},
    // Each surface (the one fluid, or each fluid's layer), at the splat's resolution.
    {"depth-splat+thickness", S::Surface, "SceneDepth, particles", "RawDepth, Thickness",
     [](const StageWhen& w) { return !sortLast(w); }, checkSplat, DRIVERS(kSplatStage)},
    // The same over several processes (RenderSettings::compositor): this share's splat, the
    // exact combination of every share's, the thickness resolved from it on the root.
    {"depth-splat", S::Surface, "SceneDepth, this share's particles", "the partial", sortLast, nullptr,
     DRIVERS(kSplatPartialStage)},
    {"composite", S::Surface, "every process's partial", "the combined partial", sortLast, nullptr, nullptr,
     nullptr, runComposite},
    {"thickness", S::Surface, "the combined partial", "RawDepth, Thickness", sortLast, nullptr,
     DRIVERS(kResolveSplatStage), runResolveSplat},
    {"fill-holes", S::Surface, "SceneDepth, RawDepth, Thickness", "RawDepth, Thickness",
     [](const StageWhen& w) { return screenPath(w) && w.settings.holeFill.enabled; }, nullptr, DRIVERS(kFillHolesStage)},
    {"smooth", S::Surface, "RawDepth", "Depth", screenPath, nullptr, DRIVERS(kSmoothStage)},
    {"normals", S::Surface, "Depth", "Normal", screenPath, nullptr, DRIVERS(kNormalsStage)},
    {"rasterise", S::Surface, "SceneDepth, the mesh", "Depth, Normal",
     [](const StageWhen& w) { return w.settings.mesh != nullptr; }, nullptr, DRIVERS(kRasteriseStage)},
    {"raycast", S::Surface, "SceneDepth, RawDepth, the field", "Depth, Normal",
     [](const StageWhen& w) { return w.settings.raycast.enabled; }, nullptr, DRIVERS(kRaycastStage)},
    {"noise", S::Surface, "Depth, Normal, particles (id, velocity)", "Noise, Normal",
     [](const StageWhen& w) { return w.settings.noise.enabled; }, checkNoise, DRIVERS(kNoiseStage)},
    // Each surface at full resolution.
    {"upsample", S::Layer, "the Low images, SceneDepth", "Depth, Normal, Thickness, Noise, Coverage", reduced,
     nullptr, DRIVERS(kUpsampleStage)},
    {"whitening", S::Layer, "Depth, particles (velocity)", "Whitening",
     [](const StageWhen& w) { return w.settings.whitening.enabled; }, checkWhitening, DRIVERS(kWhiteningStage)},
    {"shade", S::Layer, "SceneColor, SceneDepth, Depth, Normal, Thickness, Noise, Whitening",
     "Color (a layer's: its Color, Emission, Transmit)", always, nullptr, DRIVERS(kShadeStage)},
    {"fluid-edges", S::Layer, "SceneColor, Depth, Coverage, Color", "Color", reduced, nullptr, DRIVERS(kFluidEdgesStage)},
    // Once, over the picture.
    {"composite-fluids", S::Finish, "each fluid's layer", "Color, Depth, Normal, Thickness, FluidId",
     [](const StageWhen& w) { return w.severalFluids; }, nullptr, DRIVERS(kCompositeFluidsStage)},
    {"silhouette", S::Finish, "SceneColor, Depth, Color", "Color, Silhouette",
     [](const StageWhen& w) { return w.settings.silhouette.enabled; }, checkSilhouette, DRIVERS(kSilhouetteStage)},
    {"spray", S::Finish, "SceneDepth, Depth, Color, the drops", "Color, Spray",
     [](const StageWhen& w) { return drawsDrops(w.settings); }, nullptr, DRIVERS(kSprayStage)},
    {"glass", S::Finish, "SceneDepth, Depth, Color, the glass", "Color",
     [](const StageWhen& w) { return drawsGlass(w.settings.geometry.get()); }, nullptr, DRIVERS(kGlassStage)},
    // After the stages, render() reads the images it returns back to the host.
    {"readback", S::Readback, "Color and the AOVs", "the host's Aovs", always, nullptr, nullptr, nullptr},
};

}  // namespace

std::span<const StageDecl> frameStages() { return kStages; }

Status checkStages(const RenderSettings& s) {
    for (const StageDecl& stage : kStages)
        if (stage.check)
            if (auto st = stage.check(s); !st) return st;
    return okStatus();
}

const StageDriver* driverFor(const StageDecl& stage, const Backend& b) {
    return b.kind() == BackendKind::Cpu ? stage.cpu : stage.gl;
}

void StageRun::drive() { driverFor(*stage, backend)->run(backend, io); }

Status prepareStages(Backend& b) {
    for (const StageDecl& stage : kStages) {
        const StageDriver* driver = driverFor(stage, b);
        if (driver && driver->prepare)
            if (auto st = driver->prepare(b); !st)
                return makeError(st.error().file, std::string("preparing the stage ") + stage.name + ": " +
                                                      st.error().message);
    }
    return okStatus();
}

Status runStage(Backend& b, std::string_view name, const StageIo& io) {
    for (const StageDecl& stage : kStages) {
        if (stage.name != name) continue;
        const StageDriver* driver = driverFor(stage, b);
        if (!driver) return makeError("", "the stage " + std::string(name) + " has no driver on " + b.name());
        if (driver->prepare)
            if (auto st = driver->prepare(b); !st) return st;
        driver->run(b, io);
        return b.stageStatus(stage.name);
    }
    return makeError("", "no stage is named " + std::string(name));
}

Status runHostStages(const StageWhen& when, HostRun& r) {
    for (const StageDecl& stage : kStages)
        if (stage.scope == StageScope::Host && stage.runs(when))
            if (auto st = stage.host(r); !st) return st;
    return okStatus();
}

Status runScope(StageScope scope, const StageWhen& when, StageRun& r, bool timed) {
    for (const StageDecl& stage : kStages) {
        if (stage.scope != scope || !stage.runs(when)) continue;
        if (!stage.run && !driverFor(stage, r.backend))
            return makeError("", std::string("the stage ") + stage.name + " has no driver on " + r.backend.name());
        const std::string name = r.tag + stage.name;
        r.stage = &stage;
        r.io.partial = &r.partial;
        r.io.fluids = r.fluidOfLayer;
        if (timed) r.backend.beginStage(name.c_str());
        Status ran = okStatus();
        if (stage.run) ran = stage.run(r);
        else r.drive();
        if (timed) r.backend.endStage();
        // The backend's failure first (a GL error, out of GPU memory, a lost context).
        if (auto st = r.backend.stageStatus(name.c_str()); !st) return st;
        if (!ran) return ran;
        if (r.handedOver) return okStatus();
    }
    return okStatus();
}

}  // namespace meniscus
