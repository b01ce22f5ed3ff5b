// The screen-space pipeline's public entry point. The stage order lives in
// src/render/pipeline.cpp and nowhere else.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "meniscus/camera.h"
#include "meniscus/geometry.h"
#include "meniscus/io.h"
#include "meniscus/mesh.h"
#include "meniscus/params.h"
#include "meniscus/particle_view.h"
#include "meniscus/result.h"
#include "meniscus/sort_last.h"
#include "meniscus/types.h"

namespace meniscus {

// What the colour AOV (and so the PNG) shows: the shaded, composited image or
// a picture of one intermediate stage for a person to look at.
// The key light's shadows (docs/geometry.md#shadows): Auto draws them when
// the scene geometry has a visible object.
enum class ShadowMode { Auto, On, Off };

enum class View { Final, Depth, RawDepth, Normals, Thickness, Noise, Foam, Whitening, Spray, Silhouette, FluidId };

// Diffuse particles for RenderSettings::diffuse: world positions, velocities
// (m/s; empty: round drops) and each one's kind in the whitewater numbering
// (include/meniscus/whitewater.h: 0 foam, 1 spray, 2 bubble; empty: all
// spray). Foam is drawn lifted defaults::kDiffuseFoamLiftRadii particle radii toward the
// eye, so the surface it floats on does not hide it; bubbles are under the
// surface and are not drawn. The spans must outlive the render call.
struct DiffuseLayer {
    std::span<const glm::vec3> positions;
    std::span<const glm::vec3> velocities;
    std::span<const std::int64_t> kind;
    bool empty() const { return positions.empty(); }
};

// CLI names: final, depth, raw-depth, normals, thickness, noise, foam (these
// two need RenderSettings::noise enabled), whitening (RenderSettings::whitening),
// spray (RenderSettings::spray or a diffuse layer), silhouette (RenderSettings::silhouette),
// fluid-id (which fluid is nearest: one colour per fluid index).
bool viewFromName(const std::string& name, View* out);
std::string viewNames();

// The most fluids a frame may hold: fluid indices 0 .. kMaxFluids - 1.
inline constexpr int kMaxFluids = 4;

// The stages' own parameters (StageParams, params.h: the filter, thickness,
// hole filling, shading, noise, whitening, spray, silhouette, ray cast) and
// what the whole frame needs besides.
struct RenderSettings : StageParams {
    Camera camera;           // must be valid (see validateCamera / autoFrameCamera)
    float radiusM = 0.0f;    // particle radius in metres, > 0
    View view = View::Final;
    SceneParams scene;
    // Several fluids (docs/pipeline.md#several-fluids; Instant Liquids §5):
    // when the particles carry a fluid index (ParticleView::fluid, 0 ..
    // kMaxFluids - 1; another value is an error), fluid k is drawn with
    // fluidMaterials[k] (shading.material when k is past the end), splatted,
    // smoothed and shaded on its own and composited front to back with the
    // others, so different bodies are never smoothed together and each absorbs
    // with its own colour. Not on the mesh path (an error).
    // The fluid AOV is the nearest fluid's index; with several fluids the
    // noise, foam and whitening AOVs are the nearest fluid's own.
    std::vector<Material> fluidMaterials;
    // Diffuse particles drawn as drops over the surface with the spray's look
    // (its size, streak, opacity, colour), spray on or off: the whitewater of
    // `meniscus whitewater` (Ihmsen et al. 2012). Empty: none.
    DiffuseLayer diffuse;
    // Anisotropic kernels (Yu & Turk 2013): off unless anisotropy.enabled.
    // The depth splat and the thickness draw each particle as the ellipsoid
    // of its neighbourhood, centred on its smoothed position (each fluid's
    // own, with several); the other stages use the smoothed positions too.
    AnisotropyParams anisotropy;
    // The particles' own radii (ParticleView::radius, e.g. a file's radius or
    // pscale attribute; variable resolution): when present and this is set,
    // the splat and the thickness draw each particle at its own radius (and
    // the anisotropy keeps each one's own volume); radiusM still sizes the
    // filters, normals and the other stages' kernels. An error when a radius
    // is not a positive number of metres in range (checkRadius).
    bool particleRadii = true;
    // Reduced-resolution processing (docs/pipeline.md#reduced-resolution; the
    // NVIDIA patent; Instant Liquids §5): 1 (off), 0.5 or 0.25: the splat,
    // smoothing, normals and noise run at that fraction of the width and
    // height, and the surface is brought back to full resolution by depth-aware
    // upsampling (never across a silhouette or a depth jump; edges blended into
    // the scene) before the shading, which stays at full resolution. The
    // raw-depth AOV is then the low splat, each full pixel taking its nearest
    // low pixel. Not with `mesh` (an error). Any other value is an error.
    float fluidScale = defaults::kFluidScale;
    // This frame's index in its sequence, for the turbulence of the noise: the
    // renderer remembers the velocities of the last frame it rendered, and
    // compares when this index is the next one (a redraw of the same index
    // keeps its result; any other jump starts afresh). -1: a lone frame.
    std::int64_t frameIndex = -1;
    // The mesh path: when set, the surface is this triangle mesh
    // (world space, metres; e.g. from the isosurface extraction) instead of
    // the smoothed particle depth: its triangles are rasterised into the depth
    // and normal AOVs in place of the smoothing and normals stages, and shaded
    // like the screen-space surface. The particles still give the thickness,
    // the raw-depth AOV (their splat) and the framing, so pass them too. Not
    // owned; it must stay valid during render()/draw(). An error when an index
    // is out of range, a position or normal is not finite, or the normals are
    // not one per vertex.
    const TriangleMesh* mesh = nullptr;
    // The world around the liquid (include/meniscus/geometry.h,
    // docs/geometry.md): objects drawn into the scene before the liquid, in
    // the studio's light, so the liquid is hidden behind them and refracts
    // what lies behind it; the studio's floor and walls are built around them
    // and the particles together. Shared and immutable: a changed scene is a
    // new object. Null or empty: the studio alone. An error when a mesh is
    // invalid (TriangleMesh::validate with normals).
    std::shared_ptr<const SceneGeometry> geometry;
    // The key light's shadows (docs/geometry.md#shadows) of the geometry and
    // of the liquid (coloured by its absorption through its thickness seen
    // from the light) on the studio and the geometry. Auto: on when the
    // geometry has a visible object.
    ShadowMode shadows = ShadowMode::Auto;
    // Sort-last rendering over several processes
    // (include/meniscus/sort_last.h): when set, each process renders its own
    // share of the particles with the same settings, the splat runs as the
    // stages depth-splat (this share's partial), composite (the compositor
    // combines the partials of all processes; its error ends the frame) and,
    // on the root only, thickness (the combined partial resolved); the root
    // goes on with the combined image and its picture is bit-identical to
    // the one-process render of all the particles, however they were split.
    // On the others render() returns empty Aovs (every image 0 x 0) and
    // draw() does nothing more, right after the composite. Not owned; it
    // must stay valid during render()/draw(). Either backend (GL reads its
    // partial back and uploads the combination). Not yet
    // with what needs more than a share's particles or splat (each an error
    // naming its setting): noise, whitening, spray and the diffuse layer,
    // anisotropy (these five unless `share` below), raycast, the mesh path,
    // particles carrying a fluid index;
    // and scene.studioBounds must be set (the whole data's, the same on
    // every process).
    SplatCompositor* compositor = nullptr;
    // With a compositor, when every process holds the whole frame (one file
    // that each reads): the particles given to render() are all of them, the
    // same on every process, and this process splats only [share->begin,
    // share->end) of them. What needs a particle's neighbours (the anisotropic
    // kernels) is then computed from all of them, as the one-process render
    // does, so it can be on; so can the spray (its split sees every particle)
    // and, on the root, the noise, the whitening and the drops, drawn from
    // every particle after the composite (the noise and the whitening on the
    // CPU backend). Unset: the particles given are this process's own, and
    // all of these are refused.
    std::optional<ParticleRange> share;
    // Only `color` is needed (a PNG, a preview): render() leaves the other AOVs
    // empty, which on GL saves their GPU -> host copies. Every AOV otherwise
    // (an EXR).
    bool colorOnly = false;
};

// Wall-clock time of one stage of one renderFrame call.
struct StageTime {
    std::string stage;
    double ms = 0.0;
};

// Where the stages run: the CPU reference, the OpenGL backend (a headless GL
// 4.3 context made on the calling thread; the Renderer must then be used from
// that thread), or Auto = GL when a context can be created on a GPU, else the
// CPU (also when the only GL is a software rasteriser such as Mesa's llvmpipe,
// on which the CPU backend is faster).
enum class BackendChoice { Cpu, Gl, Auto };

// CLI names: cpu, gl, auto.
bool backendFromName(const std::string& name, BackendChoice* out);
std::string backendNames();

// A host application's frame the liquid is drawn into (Renderer::drawIntoHost):
// its colour and depth as textures of the GL context current on the calling
// thread, with the camera that drew them. GL_TEXTURE_2D, single-sampled (a
// multisampled target is resolved first), width x height texels, row 0 at
// the bottom as GL has it; the depth texture's compare mode GL_NONE.
struct HostLayers {
    unsigned colorTexture = 0;  // GL texture name: RGBA or RGB, read by texelFetch
    unsigned depthTexture = 0;  // GL texture name: a depth format, window depth 0 .. 1 (glDepthRange(0, 1))
    int width = 0, height = 0;  // pixels: both textures', and the frame drawn
    // The colour's values are 8-bit sRGB codes (an RGBA8 back buffer, not
    // declared GL_SRGB8_ALPHA8): decoded on reading, and the result encoded
    // again on writing, as the PNG writer does. False: linear values (a float
    // target), written back linear.
    bool colorIsSrgb = true;
    // The host's camera (OpenGL conventions, glm's column-major layout): the
    // liquid is drawn from it (cameraFromGlMatrices), and the depth texture's
    // window depth is turned into eye depth with its near and far planes.
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
};

// The particles in a GL buffer of the host's context (Renderer::drawIntoHost),
// so that nothing crosses to the CPU: `count` positions of three floats
// (metres, world space), the first `offsetBytes` into the buffer, each
// `strideBytes` after the last (12: packed xyz; 16: xyzw, w ignored; more for
// interleaved attributes). Offset and stride are multiples of 4; the buffer
// must hold every position (checked against its GL_BUFFER_SIZE). Read, never
// written, once per draw: the host may change it between draws.
struct HostParticleBuffer {
    unsigned buffer = 0;          // GL buffer name
    std::size_t count = 0;        // particles
    std::size_t offsetBytes = 0;  // bytes: of the first position
    std::size_t strideBytes = 12; // bytes: from one position to the next
    // A box (metres) holding every particle: what the shadows' light camera
    // frames (the host knows its domain; the renderer does not look at the
    // positions on the CPU). Needed only when shadows are drawn (scene
    // geometry with shadows on); empty otherwise.
    Bounds bounds;
};

class Backend;            // src/core/backend.h
class TurbulenceTracker;  // src/core/turbulence.h
struct HostFrame;         // src/render/pipeline.cpp
struct Drawn;             // src/render/pipeline.cpp

// Renders frames, keeping what does not change between them: the scene layer
// (studio colour and depth) is cast again only when the camera or the studio
// changes, so a sequence or a viewer pays for it once.
class Renderer {
public:
    Renderer();  // the CPU backend

    // A renderer on the chosen backend. Gl: an error saying why when no GL
    // context can be created (or the build has no GL). Auto: falls back to the
    // CPU and sets *note to one line saying why (no GL, or only a software one).
    static Result<Renderer> create(BackendChoice choice, std::string* note = nullptr);

    // A GL renderer on the OpenGL 4.3 context current on the calling thread (a
    // viewer's window) instead of a headless context of its own. That context
    // must outlive the renderer and be current whenever it is used, destroyed
    // included. An error when the build has no GL or no GL 4.3 context is current.
    static Result<Renderer> createOnCurrentGlContext();

    // "cpu", or "gl (<GL renderer>)".
    std::string backendName() const;
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    // Renders one frame of `particles` (positions, and the attributes later
    // stages read; a span of positions converts): every AOV is filled (color = the chosen view; depth =
    // the smoothed eye depth, or the mesh's with settings.mesh; rawDepth = the splat; normal; thickness), or
    // only color with settings.colorOnly. When
    // `timings` is given it receives one entry per stage, in pipeline order
    // (CPU: wall clock; GL: GPU time from timer queries), then, on GL, one
    // "readback" entry (wall clock of copying the AOVs back).
    Result<Aovs> render(const ParticleView& particles, const RenderSettings& settings,
                        std::vector<StageTime>* timings = nullptr);

    // For a viewer: renders one frame as render() does but keeps the colour
    // (the chosen view) on the backend for present() instead of returning the
    // AOVs. For View::Final nothing is read back; the other views are drawn on
    // the host from the read-back AOVs and handed back to the backend.
    // `timings` as for render() (without the readback entry).
    Status draw(const ParticleView& particles, const RenderSettings& settings,
                std::vector<StageTime>* timings = nullptr);

    // Draws the colour of the last draw() into the default framebuffer of the
    // current GL context (framebufferWidth x framebufferHeight pixels), its
    // top-left pixel `left` pixels from the framebuffer's left edge at the
    // top (the viewer leaves its panel's width free), one pixel per pixel,
    // encoded to 8-bit sRGB exactly as the PNG writer does; what it does not
    // cover is black. Only a renderer made by createOnCurrentGlContext() can;
    // others return an error. Does not swap the window's buffers.
    Status present(int framebufferWidth, int framebufferHeight, int left = 0);

    // Embedding (docs/compositing.md): draws the liquid into a host
    // application's frame. The host's colour and depth (HostLayers) are the
    // scene the liquid is composited into, as a backdrop is (hidden where the
    // host's depth is nearer, refracting and tinted by what lies behind), seen
    // from the host's camera, which replaces settings.camera (its size too).
    // The finished frame, the host's picture with the liquid in it, is then
    // written over every pixel of the framebuffer bound for drawing when
    // called (the host's: its colour attachment, not the textures read), with
    // its viewport. Nothing goes to the CPU; every other setting works as in
    // render(). Only a renderer made by createOnCurrentGlContext() can. GL
    // state changed: the program, vertex array, textures of units 0 and 1 and
    // shader storage bindings; depth test and blending are off afterwards; the
    // framebuffer binding and viewport are the host's again.
    Status drawIntoHost(const ParticleView& particles, const RenderSettings& settings, const HostLayers& host,
                        std::vector<StageTime>* timings = nullptr);
    // The same with the particles in the host's own GL buffer: copied on the
    // GPU into the renderer's, the anisotropic kernels made there (the GL
    // twin of the CPU's), nothing read back. The stages that need the
    // particles on the CPU cannot run so and are refused by name: the spray,
    // the surface noise, the velocity whitening, the ray cast, the mesh path;
    // a buffer carries no fluid index, own radius or colour either.
    Status drawIntoHost(const HostParticleBuffer& particles, const RenderSettings& settings, const HostLayers& host,
                        std::vector<StageTime>* timings = nullptr);

private:
    explicit Renderer(std::unique_ptr<Backend> backend);
    // Checks the settings and runs every stage; the images stay on the backend.
    Status runStages(const ParticleView& particles, const RenderSettings& settings,
                     std::vector<StageTime>* timings);
    // The noise's per-particle inputs of this frame (FrameSettings::noiseIdz, noiseAmplitude).
    void prepareNoise(const ParticleView& particles, const RenderSettings& settings);
    // The last runStages's stage times: the host's stages, then the backend's.
    void collectTimes(std::vector<StageTime>& timings);
    // What the last runStages drew, for reading it back.
    Drawn drawn(const RenderSettings& settings) const;
    std::unique_ptr<Backend> backend_;
    bool prepared_ = false;  // the stages' drivers made ready on backend_ (render/stages.h prepareStages)
    std::vector<float> noiseIdz_, noiseAmplitude_, whiteness_;
    std::unique_ptr<TurbulenceTracker> turbulence_;
    std::int64_t turbulenceFrame_ = -1;  // the frameIndex noiseAmplitude_ belongs to; -1 = none
    // The host stages' buffers and this frame's results (the spray's split,
    // the fluids, the field, the shapes, their times).
    std::unique_ptr<HostFrame> host_;
    // The host's layers during a drawIntoHost call, else null; and the host's
    // particle buffer when the particles come from it.
    const HostLayers* embed_ = nullptr;
    const HostParticleBuffer* hostParticles_ = nullptr;
    // drawIntoHost's work, for either source of particles.
    Status drawIntoHostWith(const ParticleView& particles, const RenderSettings& settings, const HostLayers& host,
                            std::vector<StageTime>* timings);
};

// One frame with a fresh Renderer (nothing cached).
Result<Aovs> renderFrame(const ParticleView& particles, const RenderSettings& settings,
                         std::vector<StageTime>* timings = nullptr);

}  // namespace meniscus
