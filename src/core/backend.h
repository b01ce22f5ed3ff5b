// The backend interface the stage list runs on (src/render/stages.cpp): the
// frame, images named by opaque handles, and each stage's driver per kind of
// backend (StageDriver), defined in the stage's own file. The CPU reference
// (src/cpu/cpu_backend.h) and the GL backend (src/gl/gl_backend.h) implement
// it; each keeps its own storage per handle (CPU: Image<T>; GL: GPU
// buffers), so the pipeline never touches pixels.
// No GL header is included here or by anything outside src/gl/.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/anisotropy.h"
#include "core/sph_field.h"
#include "meniscus/camera.h"
#include "meniscus/mesh.h"
#include "meniscus/params.h"
#include "meniscus/particle_view.h"
#include "meniscus/renderer.h"
#include "meniscus/result.h"
#include "meniscus/sort_last.h"
#include "meniscus/types.h"
#include "shared/fluids.h"
#include "shared/environment.h"
#include "shared/studio.h"

namespace meniscus {

// The key light's camera for the shadows (core/shadow_camera.h, shadowLight):
// a square image just covering the particles and the scene geometry.
struct ShadowLight {
    Camera camera;        // square, shared::kShadowMapPx a side
    float texelM = 0.0f;  // a texel's side at the bounds' centre (m)
};

// Where Backend::present draws: width x height pixels of the default
// framebuffer with the image's top-left `left` pixels from its left edge, or
// (hostFramebuffer: embedding) of the framebuffer that was bound for drawing
// when the frame began, whose viewport is given back afterwards;
// sRGB-encoded to 8-bit levels as the PNG writer does, or (srgb false) the
// linear values as they are, for a float target.
struct PresentTarget {
    int width = 0, height = 0, left = 0;
    bool hostFramebuffer = false;
    bool srgb = true;
};

// Opaque handles of the images one frame passes between stages.
// The Low* slots and Coverage hold the reduced-resolution pass
// (docs/pipeline.md#reduced-resolution); FluidId and the layer slots after
// FirstLayer (layerSlot) the several fluids (docs/pipeline.md#several-fluids);
// the Light* slots the key light's maps of the shadows (docs/geometry.md#shadows):
// the geometry's depth, the liquid's nearest depth and its thickness seen from the light.
// None: no image (an output not wanted).
enum class Slot {
    SceneColor, SceneDepth, RawDepth, Thickness, Depth, Normal, Noise, Whitening, Color, Spray, Silhouette,
    LowSceneDepth, LowThickness, LowDepth, LowNormal, LowNoise, Coverage, FluidId, LightDepth, LightRaw,
    LightThickness, FirstLayer,
    None = -1
};

// The images each fluid of several keeps until they are composited (and its
// noise and whitening maps, for the AOVs).
enum class LayerImage { RawDepth, Depth, Normal, Thickness, Color, Emission, Transmit, Noise, Whitening };
inline constexpr int kLayerImageCount = 9;
// Layer `layer`'s (0 .. shared::kMaxFluids - 1) image `what`.
inline Slot layerSlot(int layer, LayerImage what) {
    return Slot(int(Slot::FirstLayer) + layer * kLayerImageCount + int(what));
}
inline constexpr int kSlotCount = int(Slot::FirstLayer) + shared::kMaxFluids * kLayerImageCount;

// What changes from one fluid to the next within a frame (Backend::setFluid):
// its particles (views valid for this frame only), its material, and its
// particles' noise and whitening inputs (as FrameSettings' spans).
struct FluidSettings {
    ParticleView particles;
    std::span<const EllipsoidShape> shapes;  // as FrameSettings::shapes
    const SphField* field = nullptr;         // as FrameSettings::field
    ShadingParams shading;
    std::span<const float> noiseIdz;
    std::span<const float> noiseAmplitude;
    std::span<const float> whiteness;
};

// Everything the stages read besides images, resolved once per frame: the
// stages' parameters (StageParams, from RenderSettings whole; the shading is
// the current fluid's) and the frame's own inputs.
struct FrameSettings : StageParams {
    Camera camera;
    float radius = 0.0f;
    // Anisotropic kernels (core/anisotropy.h): one ellipsoid per position of
    // beginFrame (this frame only), splatted for depth and thickness instead
    // of the spheres of `radius`; empty: spheres. The other stages keep the radius.
    std::span<const EllipsoidShape> shapes;
    // Or, with deviceAnisotropy (a backend that computes the ellipsoids
    // itself: GL, gl/anisotropy.h), `shapes` is empty and the backend makes
    // them (and the smoothed centres) from beginFrame's positions with these
    // parameters, the own radii deviceRadii (empty: `radius`), every shape
    // scaled by deviceShapeScale (the ray cast's coverRadii; else 1).
    const AnisotropyParams* deviceAnisotropy = nullptr;
    std::span<const float> deviceRadii;
    float deviceShapeScale = 1.0f;
    // Whether the frame's stages are timed (the backend's own work in
    // beginFrame is bracketed as a stage too).
    bool timed = false;
    // The SPH surface, ray cast (docs/pipeline.md#ray-cast-surface), when
    // raycast.enabled: the particles' field (this frame only, the Renderer's)
    // the raycast stage reads.
    const SphField* field = nullptr;
    // The surface noise (docs/pipeline.md#noise-and-foam), per particle (this
    // frame only, pointing into the Renderer's memory): the noise's third
    // coordinate (shared::noiseIdCoordinate of the id) and the turbulence
    // factor (empty: 1).
    std::span<const float> noiseIdz;
    std::span<const float> noiseAmplitude;
    // The velocity whitening (docs/pipeline.md#noise-and-foam), per particle
    // (this frame only): its whiteness (shared::whitenessOfSpeed; empty: 0).
    std::span<const float> whiteness;
    // The spray's drops (docs/pipeline.md#classification), taken out of the
    // particles above, which are the body of water: world positions and
    // velocities (m/s; empty: round drops).
    std::span<const glm::vec3> sprayPositions;
    std::span<const glm::vec3> sprayVelocities;
    shared::Studio studio;
    // The environment map (docs/pipeline.md#environment-map), pointing into
    // RenderSettings::scene.environment (valid for this frame), or disabled
    // (texels null): the procedural sky of src/shared/sky.h.
    shared::EnvironmentMap environment;
    // The image `environment` points into: a backend that keeps what it drew
    // with the map (the scene cast, the GPU copy) holds it too, so a new map
    // cannot take the old one's address while the cache compares addresses.
    std::shared_ptr<const EnvironmentImage> environmentImage;
    // The backdrop (RenderSettings::scene.backdrop, its size checked by the
    // Renderer), or null: the studio. The scene stage makes its layer
    // (core/backdrop_layer.h) and keeps it while backdrop and camera stay.
    std::shared_ptr<const BackdropImage> backdrop;
    // Embedding (Renderer::drawIntoHost): the host's colour and depth textures
    // are the scene layer instead (read again every frame), or null. Only the
    // GL backend has them.
    const HostLayers* hostLayers = nullptr;
    // And the host's own particle buffer (drawIntoHost with a
    // HostParticleBuffer): beginFrame's positions are then empty and the GL
    // backend copies the particles from it on the GPU; or null.
    const HostParticleBuffer* hostParticles = nullptr;
    // Reduced-resolution processing (docs/pipeline.md#reduced-resolution): the
    // divisor d of the fluid scale (1: off), and the depth jump (metres) the
    // upsampling does not blend across.
    int fluidDivisor = 1;
    float upsampleJumpM = 0.0f;
    // The particles' views (attributes for the stages that read them; the
    // positions also come contiguous as beginFrame's argument). Valid for
    // this frame only: they point into the caller's memory.
    ParticleView particles;
    // The mesh of the mesh path (RenderSettings::mesh, checked by the
    // Renderer), or null. Valid for this frame only.
    const TriangleMesh* mesh = nullptr;
    // The scene geometry (RenderSettings::geometry, checked by the Renderer),
    // or null: drawn into the scene layer by the geometry stage. Shared, so a
    // backend may keep what it drew of it while it stays the same object.
    std::shared_ptr<const SceneGeometry> geometry;
    // The key light's camera of the shadow stages (shadowLight), made once per
    // frame by the Renderer when the frame draws shadows (a zero-sized camera
    // otherwise: the shadow stages then draw nothing).
    ShadowLight shadow;
    // Sort-last rendering (RenderSettings::compositor, meniscus/sort_last.h),
    // or null: the Renderer then runs splatPartial, the compositor and
    // resolveSplat in place of splat. The backends only carry it (for a
    // backend that would have to refuse it, or composite on its own).
    SplatCompositor* compositor = nullptr;
    // Sort-last over the whole frame with stages after the composite that
    // read every particle (the noise, the whitening): splatPartial splats
    // only these of beginFrame's positions (and shapes); the other stages see
    // all of them. Unset: all of them. The CPU backend only (the Renderer
    // refuses it on another).
    std::optional<ParticleRange> splatRange;

    // The fluid the stages draw from now on (Backend::setFluid): its
    // particles, shapes, field, material and per-particle inputs.
    void useFluid(const FluidSettings& fluid) {
        particles = fluid.particles;
        shapes = fluid.shapes;
        deviceAnisotropy = nullptr;  // several fluids: the shapes come made
        field = fluid.field;
        shading = fluid.shading;
        noiseIdz = fluid.noiseIdz;
        noiseAmplitude = fluid.noiseAmplitude;
        whiteness = fluid.whiteness;
    }
};

class Backend;

enum class BackendKind { Cpu, Gl };

// The images one stage call reads and writes, by their role. The stage list
// (src/render/stages.cpp) points them at the surface being drawn: the full
// image's, the low one's of reduced resolution, or one fluid's layer; a test
// may point them anywhere. emission and transmit: the colour's split
// C = E + T S of several fluids (shared/fluids.h), Slot::None without.
struct StageSlots {
    Slot sceneColor = Slot::SceneColor, sceneDepth = Slot::SceneDepth;
    Slot raw = Slot::RawDepth, thickness = Slot::Thickness, depth = Slot::Depth, normal = Slot::Normal;
    Slot noise = Slot::Noise, whitening = Slot::Whitening;
    Slot color = Slot::Color, emission = Slot::None, transmit = Slot::None;
    Slot silhouette = Slot::Silhouette, spray = Slot::Spray, coverage = Slot::Coverage, fluidId = Slot::FluidId;
};

// One stage call: its images, and what passes between stages besides images.
struct StageIo {
    StageSlots at;
    // Sort-last (FrameSettings::compositor): this process's depth and
    // fixed-point chords (depth-splat), then the combination resolved into
    // the depth and thickness (thickness; the depth may be moved out).
    SplatPartial* partial = nullptr;
    // composite-fluids: layer i's fluid index (its layerSlot images).
    std::span<const int> fluids;
};

// A stage's driver on one kind of backend, defined in the stage's own file
// (src/cpu/<stage>.cpp, src/gl/<stage>.cpp) and named by the stage's row in
// the list, so no central interface grows a method per stage.
struct StageDriver {
    // Makes what the stage needs once per backend (GL: its shader programs);
    // an error says what failed. nullptr: nothing to make.
    Status (*prepare)(Backend&);
    // Runs the stage on the current frame (beginFrame's particles and settings).
    void (*run)(Backend&, const StageIo&);
};

// The backend the stages run on: the frame's particles and settings, the
// images kept per slot (CPU: Image<T>; GL: GPU buffers), timing, read-back
// and display. The stages themselves are drivers (StageDriver) of each kind.
class Backend {
public:
    virtual ~Backend() = default;

    // "cpu", or "gl (<GL_RENDERER>)".
    virtual std::string name() const = 0;

    // Starts a frame: the particles and the settings every stage reads.
    virtual Status beginFrame(std::span<const glm::vec3> positions, const FrameSettings& settings) = 0;

    // Which kind it is: the stage list (src/render/stages.cpp) runs each
    // stage through this kind's driver.
    virtual BackendKind kind() const = 0;

    // ---- Several fluids (docs/pipeline.md#several-fluids). The particles and
    // material the stages after this call draw (one fluid of the frame), until
    // the next call.
    virtual void setFluid(std::span<const glm::vec3> positions, const FluidSettings& fluid) = 0;

    // ---- Reduced-resolution processing (docs/pipeline.md#reduced-resolution).
    // The camera the stages after this call run at (the low camera,
    // core/fluid_scale.h, then the full one again); the particles and the other
    // settings stay.
    virtual void setCamera(const Camera& camera) = 0;

    // Whether the stage just run (or the read-back) failed: OK, or an error
    // naming `stage` and what went wrong (GL: a GL error, GPU memory, a lost
    // context). The pipeline asks after every stage and stops at the first
    // failure, so no garbage image is returned. CPU stages report failure by
    // throwing (bad_alloc), which the Renderer turns into an error.
    virtual Status stageStatus(const char* stage) = 0;

    // ---- Timing: when timings are asked for, the pipeline brackets each
    // stage; stageTimes() returns one entry per bracket of this frame, in order
    // (CPU: wall clock; GL: GPU timer queries, or the wall time of the stage
    // when the driver's queries read 0, as llvmpipe's do).
    virtual void beginStage(const char* name) = 0;
    virtual void endStage() = 0;
    virtual std::vector<StageTime> stageTimes() = 0;

    // ---- Read back (GL: waits for the GPU). The backend may hand its storage
    // over: a slot read back holds nothing until a stage writes it again
    // (the scene slots excepted, which stay cached).
    virtual Image<float> readScalar(Slot slot) = 0;
    virtual Image<glm::vec3> readVec3(Slot slot) = 0;
    virtual Image<glm::vec4> readColor(Slot slot) = 0;

    // ---- Display (a viewer's window).
    // Puts a host image into a colour slot (a debug view drawn on the host).
    virtual void writeColor(Slot slot, Image<glm::vec4> image) = 0;
    // Draws the colour slot into a framebuffer of the current GL context
    // (PresentTarget: the window's, or the host's bound one when embedding).
    // Only a GL backend made on a context that is not its own can; the others
    // return an error.
    virtual Status present(Slot color, const PresentTarget& target) = 0;
};

// The CPU reference backend (always available).
std::unique_ptr<Backend> makeCpuBackend();

// The GL backend on the GL 4.3 context current on the calling thread (a
// window's, gl::Window) rather than a headless one of its own; that context
// must outlive the backend and be current whenever it is used. An error when
// the build has no GL or the current context is not GL 4.3.
Result<std::unique_ptr<Backend>> makeGlBackendOnCurrentContext();

// The backend for a choice: CPU; GL (an error when no context can be made or
// the build has no GL); Auto = GL when a context can be made, else the CPU
// with *note set to one line saying why.
Result<std::unique_ptr<Backend>> makeBackend(BackendChoice choice, std::string* note);

}  // namespace meniscus
