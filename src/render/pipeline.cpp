// The stage order of the screen-space pipeline (docs/conventions.md#data-flow),
// in one place:
//   scene -> depth splat + thickness (one pass) -> [hole filling] -> smoothing -> normals
//         -> [surface noise: N and bumped normals] -> [velocity whitening map]
//         -> shading (+ foam, + white water) -> [silhouette reduction] -> [spray drops],
// with reduced resolution (RenderSettings::fluidScale < 1,
// docs/pipeline.md#reduced-resolution) the splat, smoothing, normals and noise
// on the low camera between the scene and an upsample stage, and the fluid's
// edges blended into the scene after the shading; with several fluids
// (docs/pipeline.md#several-fluids), per fluid present the splat, smoothing,
// normals, [noise], [whitening] and shading into its own layer (at reduced
// resolution with its own upsample and fluid-edges), then
//   composite-fluids (front to back per pixel) -> [silhouette] -> [spray];
// or, on the mesh path (RenderSettings::mesh):
//   scene -> depth splat + thickness -> rasterise the mesh -> [noise] -> [whitening] -> shading
//         -> [silhouette] -> [spray].
// With a compositor (sort-last over several processes, meniscus/sort_last.h)
// the splat is three stages, depth-splat -> composite -> thickness, and a
// process other than the root stops after the composite.
// With the spray on, the particles classified as spray (core/spray.h) are
// taken out before the splat and drawn by the last stage, which also draws
// the diffuse layer (RenderSettings::diffuse, the whitewater) when given.
// Each stage is declared in render/stages.cpp (what it reads and writes, when
// it runs, the check of its parameters) and runs as one method of the backend
// (src/core/backend.h): one function in src/cpu/ on the CPU, one shader stage
// in src/gl/ on the GL backend.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <limits>
#include <new>
#include <string>
#include <string_view>

#include "core/anisotropy.h"
#include "core/sph_field.h"
#include "core/backend.h"
#include "core/fluid_scale.h"
#include "core/frame_memory.h"
#include "core/shadow_camera.h"
#include "core/spray.h"
#include "core/turbulence.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "render/stages.h"
#include "shared/environment.h"
#include "shared/raster_mesh.h"
#include "shared/studio.h"
#include "shared/surface_noise.h"
#include "shared/thickness.h"
#include "shared/velocity_map.h"

namespace meniscus {

static_assert(kMaxFluids == shared::kMaxFluids, "one limit for the API and the shaders");

// What a frame drew, for reading it back: the effects that were on, and the
// fluids (several: each composited layer's fluid index; one: its index, -1
// when the particles carry none).
struct Drawn {
    bool noise = false, whitening = false, spray = false, silhouette = false;
    std::vector<int> layerFluids;
    int singleFluid = -1;
};

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- Debug views: pictures of one stage for a person (not physically based).

// Near = bright, far = dark over the fluid's own depth range; no fluid = dark.
Image<glm::vec4> depthView(const Image<float>& depth) {
    float zmin = kInf, zmax = 0.0f;
    for (float z : depth.pixels)
        if (z < kInf) {
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
        }
    const float span = zmax > zmin ? zmax - zmin : 1.0f;
    Image<glm::vec4> out(depth.width, depth.height, glm::vec4(0.02f, 0.02f, 0.025f, 0.0f));
    for (std::size_t i = 0; i < depth.size(); ++i) {
        const float z = depth.pixels[i];
        if (!(z < kInf)) continue;
        const float s = 1.0f - 0.85f * (z - zmin) / span;  // 1 at the nearest fluid, 0.15 at the farthest
        out.pixels[i] = glm::vec4(s * s * glm::vec3(0.85f, 0.92f, 1.0f), 1.0f);
    }
    return out;
}

// The usual normal-map colours: rgb = n * 0.5 + 0.5 (view space), linearised so
// the sRGB PNG shows exactly those values.
Image<glm::vec4> normalsView(const Image<glm::vec3>& normals, const Image<float>& depth) {
    Image<glm::vec4> out(normals.width, normals.height, glm::vec4(0.0f));
    for (std::size_t i = 0; i < normals.size(); ++i) {
        if (!(depth.pixels[i] < kInf)) continue;
        const glm::vec3 c = normals.pixels[i] * 0.5f + 0.5f;
        out.pixels[i] = glm::vec4(glm::pow(c, glm::vec3(2.2f)), 1.0f);
    }
    return out;
}

// The 99th percentile of `values` (reordered), the top of a view's colour
// scale so that a few outliers do not wash it out; 1 when there are none.
float percentile99(std::vector<float>& values) {
    if (values.empty()) return 1.0f;
    auto k = values.begin() + std::ptrdiff_t(0.99 * double(values.size() - 1));
    std::nth_element(values.begin(), k, values.end());
    return std::max(*k, 1e-30f);
}

// Thickness as a heat ramp (black - blue - cyan - white) up to the 99th percentile.
Image<glm::vec4> thicknessView(const Image<float>& thickness) {
    std::vector<float> values;
    for (float t : thickness.pixels)
        if (t > 0.0f) values.push_back(t);
    const float top = percentile99(values);
    Image<glm::vec4> out(thickness.width, thickness.height, glm::vec4(0.0f));
    for (std::size_t i = 0; i < thickness.size(); ++i) {
        const float t = thickness.pixels[i];
        if (!(t > 0.0f)) continue;
        const float u = std::min(1.0f, t / top);
        const glm::vec3 c = u < 0.5f ? glm::mix(glm::vec3(0.0f, 0.02f, 0.15f), glm::vec3(0.0f, 0.55f, 0.9f), 2.0f * u)
                                     : glm::mix(glm::vec3(0.0f, 0.55f, 0.9f), glm::vec3(1.0f), 2.0f * u - 1.0f);
        out.pixels[i] = glm::vec4(c, 1.0f);
    }
    return out;
}

// Signed noise: orange where N > 0, blue where N < 0, up to the 99th
// percentile of |N| over the fluid; grey fluid where N = 0, dark elsewhere.
Image<glm::vec4> noiseView(const Image<float>& noise, const Image<float>& depth) {
    std::vector<float> values;
    for (std::size_t i = 0; i < noise.size(); ++i)
        if (depth.pixels[i] < kInf && noise.pixels[i] != 0.0f) values.push_back(std::fabs(noise.pixels[i]));
    const float top = percentile99(values);
    Image<glm::vec4> out(noise.width, noise.height, glm::vec4(0.02f, 0.02f, 0.025f, 0.0f));
    for (std::size_t i = 0; i < noise.size(); ++i) {
        if (!(depth.pixels[i] < kInf)) continue;
        const float u = std::clamp(noise.pixels[i] / top, -1.0f, 1.0f);
        const glm::vec3 grey(0.18f), pos(1.0f, 0.45f, 0.05f), neg(0.05f, 0.35f, 1.0f);
        out.pixels[i] = glm::vec4(glm::mix(grey, u > 0.0f ? pos : neg, std::fabs(u)), 1.0f);
    }
    return out;
}

// Foam cover (or the whitening map) as grey levels over the fluid (white = 1).
Image<glm::vec4> foamView(const Image<float>& foam, const Image<float>& depth) {
    Image<glm::vec4> out(foam.width, foam.height, glm::vec4(0.02f, 0.02f, 0.025f, 0.0f));
    for (std::size_t i = 0; i < foam.size(); ++i)
        if (depth.pixels[i] < kInf) out.pixels[i] = glm::vec4(glm::vec3(0.03f + 0.97f * foam.pixels[i]), 1.0f);
    return out;
}

// A cover (the spray's) as grey levels over the whole image, dark where none.
Image<glm::vec4> coverView(const Image<float>& cover) {
    Image<glm::vec4> out(cover.width, cover.height, glm::vec4(0.02f, 0.02f, 0.025f, 0.0f));
    for (std::size_t i = 0; i < cover.size(); ++i)
        if (cover.pixels[i] > 0.0f) out.pixels[i] = glm::vec4(glm::vec3(0.03f + 0.97f * cover.pixels[i]), 1.0f);
    return out;
}

// Which fluid is nearest: one colour per fluid index, dark where none.
Image<glm::vec4> fluidIdView(const Image<float>& fluid) {
    static const glm::vec3 kPalette[shared::kMaxFluids] = {
        {0.05f, 0.30f, 0.90f}, {0.95f, 0.40f, 0.03f}, {0.15f, 0.75f, 0.20f}, {0.80f, 0.15f, 0.70f}};
    Image<glm::vec4> out(fluid.width, fluid.height, glm::vec4(0.02f, 0.02f, 0.025f, 0.0f));
    for (std::size_t i = 0; i < fluid.size(); ++i) {
        const int k = int(fluid.pixels[i]);
        if (k >= 0 && k < shared::kMaxFluids) out.pixels[i] = glm::vec4(kPalette[k], 1.0f);
    }
    return out;
}

// The foam AOV: the cover the shading laid over each fluid pixel.
Image<float> foamCover(const Image<float>& noise, const NoiseParams& p) {
    Image<float> out(noise.width, noise.height, 0.0f);
    for (std::size_t i = 0; i < noise.size(); ++i)
        out.pixels[i] = shared::noiseFoamCover(noise.pixels[i], p.foamThreshold, p.foamGain);
    return out;
}

// The raw splat of several fluids: per pixel the nearest layer's.
Image<float> nearestRawDepth(Backend& b, int layers) {
    Image<float> out = b.readScalar(layerSlot(0, LayerImage::RawDepth));
    for (int l = 1; l < layers; ++l) {
        const Image<float> z = b.readScalar(layerSlot(l, LayerImage::RawDepth));
        for (std::size_t i = 0; i < out.size(); ++i) out.pixels[i] = std::min(out.pixels[i], z.pixels[i]);
    }
    return out;
}

// A per-layer map of several fluids (noise, whitening) as the AOV: per pixel
// the nearest fluid's (`fluid`, the fluid AOV), 0 where there is none.
Image<float> nearestFluidsMap(Backend& b, const std::vector<int>& layerFluids, const Image<float>& fluid,
                              LayerImage what) {
    Image<float> out(fluid.width, fluid.height, 0.0f);
    for (std::size_t l = 0; l < layerFluids.size(); ++l) {
        const Image<float> m = b.readScalar(layerSlot(int(l), what));
        for (std::size_t i = 0; i < out.size() && i < m.size(); ++i)
            if (fluid.pixels[i] == float(layerFluids[l])) out.pixels[i] = m.pixels[i];
    }
    return out;
}

// Reads back what the output needs: every AOV, or (colorOnly) the colour or
// the stages the debug view pictures.
Aovs readAovs(Backend& b, View v, bool colorOnly, const NoiseParams& noiseParams, const Drawn& d) {
    const bool all = !colorOnly;
    const bool noiseView = v == View::Noise || v == View::Foam || v == View::Whitening || v == View::Spray ||
                           v == View::Silhouette || v == View::FluidId;
    const bool several = !d.layerFluids.empty();
    Aovs aovs;
    if (all || v == View::RawDepth)
        aovs.rawDepth = several ? nearestRawDepth(b, int(d.layerFluids.size())) : b.readScalar(Slot::RawDepth);
    if (all || v == View::Depth || v == View::Normals || noiseView) aovs.depth = b.readScalar(Slot::Depth);
    if (all || v == View::Thickness) aovs.thickness = b.readScalar(Slot::Thickness);
    if (all || v == View::Normals) aovs.normal = b.readVec3(Slot::Normal);
    if (all || v == View::Final) aovs.color = b.readColor(Slot::Color);
    if (d.spray && (all || v == View::Spray)) aovs.spray = b.readScalar(Slot::Spray);
    if (d.silhouette && (all || v == View::Silhouette)) aovs.silhouette = b.readScalar(Slot::Silhouette);
    const bool noise = d.noise && (all || noiseView), whitening = d.whitening && (all || v == View::Whitening);
    if (several && (all || v == View::FluidId || noise || whitening)) aovs.fluid = b.readScalar(Slot::FluidId);
    // Several fluids: each drew its own noise and whitening; the nearest one's.
    if (noise) {
        aovs.noise = several ? nearestFluidsMap(b, d.layerFluids, aovs.fluid, LayerImage::Noise)
                             : b.readScalar(Slot::Noise);
        aovs.foam = foamCover(aovs.noise, noiseParams);
    }
    if (whitening)
        aovs.whitening = several ? nearestFluidsMap(b, d.layerFluids, aovs.fluid, LayerImage::Whitening)
                                 : b.readScalar(Slot::Whitening);
    // One fluid (several were read above): its index wherever there is fluid.
    if ((all || v == View::FluidId) && !several && d.singleFluid >= 0) {
        aovs.fluid = Image<float>(aovs.depth.width, aovs.depth.height, -1.0f);
        for (std::size_t i = 0; i < aovs.depth.size(); ++i)
            if (aovs.depth.pixels[i] < kInf) aovs.fluid.pixels[i] = float(d.singleFluid);
    }
    return aovs;
}

// With reduced resolution the raw splat is the low camera's: each full pixel
// takes its nearest low pixel, so every AOV has the image's size.
void rawDepthAtFullSize(const RenderSettings& s, Aovs& aovs) {
    const int d = fluidDivisor(s.fluidScale);
    if (d > 1 && !aovs.rawDepth.empty())
        aovs.rawDepth = nearestUpsample(aovs.rawDepth, s.camera.width, s.camera.height, d);
}

// Replaces the colour by the chosen debug view (Final keeps it); colorOnly
// then drops the rest.
void applyView(View view, bool colorOnly, Aovs& aovs) {
    switch (view) {
        case View::Final: break;
        case View::Depth: aovs.color = depthView(aovs.depth); break;
        case View::RawDepth: aovs.color = depthView(aovs.rawDepth); break;
        case View::Normals: aovs.color = normalsView(aovs.normal, aovs.depth); break;
        case View::Thickness: aovs.color = thicknessView(aovs.thickness); break;
        case View::Noise: aovs.color = noiseView(aovs.noise, aovs.depth); break;
        case View::Foam: aovs.color = foamView(aovs.foam, aovs.depth); break;
        case View::Whitening: aovs.color = foamView(aovs.whitening, aovs.depth); break;
        case View::Spray: aovs.color = coverView(aovs.spray); break;
        case View::Silhouette: aovs.color = foamView(aovs.silhouette, aovs.depth); break;
        case View::FluidId: aovs.color = fluidIdView(aovs.fluid); break;
    }
    if (colorOnly) {
        aovs.depth = aovs.rawDepth = aovs.thickness = aovs.noise = aovs.foam = aovs.whitening = aovs.spray =
            aovs.silhouette = aovs.fluid = {};
        aovs.normal = {};
    }
}

}  // namespace

bool viewFromName(const std::string& name, View* out) {
    static const std::pair<const char*, View> kViews[] = {{"final", View::Final},
                                                          {"depth", View::Depth},
                                                          {"raw-depth", View::RawDepth},
                                                          {"normals", View::Normals},
                                                          {"thickness", View::Thickness},
                                                          {"noise", View::Noise},
                                                          {"foam", View::Foam},
                                                          {"whitening", View::Whitening},
                                                          {"spray", View::Spray},
                                                          {"silhouette", View::Silhouette},
                                                          {"fluid-id", View::FluidId}};
    for (const auto& [n, v] : kViews)
        if (name == n) {
            *out = v;
            return true;
        }
    return false;
}

std::string viewNames() {
    return "final, depth, raw-depth, normals, thickness, noise, foam, whitening, spray, silhouette, fluid-id";
}

bool backendFromName(const std::string& name, BackendChoice* out) {
    static const std::pair<const char*, BackendChoice> kBackends[] = {
        {"cpu", BackendChoice::Cpu}, {"gl", BackendChoice::Gl}, {"auto", BackendChoice::Auto}};
    for (const auto& [n, b] : kBackends)
        if (name == n) {
            *out = b;
            return true;
        }
    return false;
}

std::string backendNames() { return "cpu, gl, auto"; }

namespace {

// The library never lets an exception out: what escapes a backend (bad_alloc
// for a frame too large for memory, a std::exception of a library it uses)
// becomes an Error naming where it happened.
template <class F>
auto guarded(const char* where, F&& run) -> decltype(run()) {
    try {
        return run();
    } catch (const std::bad_alloc&) {
        return makeError("", std::string(where) + ": out of memory");
    } catch (const std::exception& e) {
        return makeError("", std::string(where) + ": " + e.what());
    } catch (...) {
        return makeError("", std::string(where) + ": unexpected failure");
    }
}

// The mesh path's input: what TriangleMesh::validate checks, with a normal for
// every vertex (the rasterisers' preconditions).
Status checkMesh(const TriangleMesh& m) {
    if (auto st = m.validate(/*needNormals=*/true); !st)
        return makeError("", "RenderSettings::mesh: " + st.error().message);
    return okStatus();
}
// Their precondition on the image needs no check of its own: validateCamera
// (run first) refuses any side the CPU rasteriser could not hold.
static_assert(defaults::kMaxImageSizePx <= shared::kRasterMaxSidePx,
              "the mesh path needs a check of the image size against shared::kRasterMaxSidePx");

// The particles [begin, begin + count) of a view, every attribute with them.
ParticleView sliceView(const ParticleView& v, std::size_t begin, std::size_t count) {
    auto slice = [&](auto view) {
        if (view.present()) {
            view.data += begin * view.strideBytes;
            view.count = count;
        }
        return view;
    };
    ParticleView out = v;
    out.positions = slice(v.positions);
    out.velocity = slice(v.velocity);
    out.density = slice(v.density);
    out.id = slice(v.id);
    out.fluid = slice(v.fluid);
    out.color = slice(v.color);
    out.radius = slice(v.radius);
    return out;
}

// Sort-last rendering (RenderSettings::compositor) combines the splats of the
// processes' shares exactly, so everything decided by one share's particles
// (spheres, own radii) or by the combined splat (the stages after it) gives
// the one-process picture. What reads more than that is refused until it is
// composited too.
Status checkSortLast(const RenderSettings& s, const ParticleView& all) {
    auto refuse = [](const std::string& setting, const std::string& why) {
        return makeError("", "RenderSettings::" + setting +
                                 " is not composited across processes yet (RenderSettings::compositor): " + why);
    };
    // Given the whole frame (share), the root has every particle for the
    // stages after the composite, and the spray's split sees every neighbour.
    const std::string whole = "; give every process the whole frame and its RenderSettings::share";
    if (s.noise.enabled && !s.share)
        return refuse("noise", "the noise splats the particles of every share near the surface" + whole);
    if (s.whitening.enabled && !s.share)
        return refuse("whitening", "the whitening splats the particles of every share near the surface" + whole);
    if (s.spray.enabled && !s.share)
        return refuse("spray", "a drop is told from the body by its neighbours in every share" + whole);
    if (!s.diffuse.empty() && !s.share) return refuse("diffuse", "the drops are drawn over the combined image" + whole);
    if (s.anisotropy.enabled && !s.share)
        return refuse("anisotropy", "an ellipsoid needs its neighbours, which may be in another share; give every "
                                    "process the whole frame and its RenderSettings::share, or turn it off");
    if (s.share && (s.share->begin > s.share->end || s.share->end > all.size()))
        return makeError("", "RenderSettings::share: [" + std::to_string(s.share->begin) + ", " +
                                 std::to_string(s.share->end) + ") is not a range of the " +
                                 std::to_string(all.size()) + " particles");
    if (s.raycast.enabled) return refuse("raycast", "the rays march the density of every share's particles");
    if (s.mesh) return refuse("mesh", "the mesh path rasterises a mesh, not the particles' splat");
    if (all.fluid.present())
        return makeError("", "ParticleView::fluid: particles carrying a fluid index are not composited across "
                             "processes yet (RenderSettings::compositor): the fluids' layers would depend on the share");
    if (s.scene.studioBounds.empty())
        return makeError("", "RenderSettings::scene.studioBounds: must be set with RenderSettings::compositor, to "
                             "the bounds of all the processes' particles (a share's own bounds would build another "
                             "studio on each process)");
    return okStatus();
}

}  // namespace

namespace {

// Copies of some of a view's particles (positions and every attribute it
// has) with a view over them, for the stages that read a subset.
struct ParticleCopy {
    std::vector<glm::vec3> positions, velocity, color;
    std::vector<float> density, radius;
    std::vector<std::int64_t> id, fluid;
    ParticleView view;

    void gather(const ParticleView& all, std::span<const std::uint32_t> indices) {
        positions.clear(), velocity.clear(), color.clear(), density.clear(), radius.clear(), id.clear(), fluid.clear();
        for (std::uint32_t i : indices) {
            positions.push_back(all.positions[i]);
            if (all.velocity.present()) velocity.push_back(all.velocity[i]);
            if (all.color.present()) color.push_back(all.color[i]);
            if (all.density.present()) density.push_back(all.density[i]);
            if (all.radius.present()) radius.push_back(all.radius[i]);
            if (all.id.present()) id.push_back(all.id[i]);
            if (all.fluid.present()) fluid.push_back(all.fluid[i]);
        }
        view = ParticleView(std::span<const glm::vec3>(positions));
        if (all.velocity.present()) view.velocity = StridedView<glm::vec3>(std::span<const glm::vec3>(velocity));
        if (all.color.present()) view.color = StridedView<glm::vec3>(std::span<const glm::vec3>(color));
        if (all.density.present()) view.density = StridedView<float>(std::span<const float>(density));
        if (all.radius.present()) view.radius = StridedView<float>(std::span<const float>(radius));
        if (all.id.present()) view.id = StridedView<std::int64_t>(std::span<const std::int64_t>(id));
        if (all.fluid.present()) view.fluid = StridedView<std::int64_t>(std::span<const std::int64_t>(fluid));
    }
};

// `values` (one per particle of a view, or empty) at `indices`.
void gatherValues(std::span<const float> values, std::span<const std::uint32_t> indices, std::vector<float>& out) {
    out.clear();
    if (values.empty()) return;
    for (std::uint32_t i : indices) out.push_back(values[i]);
}

}  // namespace

// This frame's particles split into the body of water (a view over copies
// of its positions and attributes, for every stage up to the shading) and the
// drops the spray stage draws.
struct SpraySplit {
    ParticleCopy body;
    std::vector<std::uint32_t> kept;
    std::vector<glm::vec3> dropPositions, dropVelocities;

    void split(const ParticleView& all, const RenderSettings& s) {
        const std::vector<std::uint8_t> isSpray = classifySpray(all, s.radiusM, s.spray);
        kept.clear(), dropPositions.clear(), dropVelocities.clear();
        for (std::size_t i = 0; i < all.size(); ++i) {
            if (!isSpray[i]) {
                kept.push_back(std::uint32_t(i));
                continue;
            }
            dropPositions.push_back(all.positions[i]);
            if (all.velocity.present()) dropVelocities.push_back(all.velocity[i]);
        }
        body.gather(all, kept);
    }

    // The diffuse layer's spray and foam joined to the drops (bubbles are
    // under the surface), foam lifted toward the eye along its ray (the
    // same pixel) so the surface it floats on does not hide it. Velocities
    // are zero-filled where one source has them and the other not.
    void addDiffuse(const DiffuseLayer& d, const Camera& camera, float radius) {
        const std::size_t before = dropPositions.size();
        const bool anyVelocity = !dropVelocities.empty() || d.velocities.size() == d.positions.size();
        if (anyVelocity) dropVelocities.resize(before, glm::vec3(0.0f));
        const float lift = defaults::kDiffuseFoamLiftRadii * radius;
        for (std::size_t i = 0; i < d.positions.size(); ++i) {
            const std::int64_t kind = i < d.kind.size() ? d.kind[i] : 1;
            if (kind == 2) continue;  // a bubble
            glm::vec3 p = d.positions[i];
            if (kind == 0) {
                const glm::vec3 toEye = camera.eye - p;
                const float len = glm::length(toEye);
                if (len > lift) p += toEye * (lift / len);
            }
            dropPositions.push_back(p);
            if (anyVelocity)
                dropVelocities.push_back(d.velocities.size() == d.positions.size() ? d.velocities[i] : glm::vec3(0.0f));
        }
    }
};

// This frame's body of water grouped by fluid index
// (docs/pipeline.md#several-fluids): one group per fluid present, by index
// ascending, each with copies of its particles and of their noise and whitening
// inputs.
struct FluidSplit {
    struct Group {
        int fluid = 0;
        std::vector<std::uint32_t> indices;
        ParticleCopy particles;
        std::vector<float> idz, amplitude, whiteness;
    };
    std::vector<Group> groups;

    // Groups `all` by its fluid attribute (none: one group of fluid -1 is not
    // made, groups stays empty); an error for an index out of range.
    Status split(const ParticleView& all) {
        groups.clear();
        if (!all.fluid.present()) return okStatus();
        std::size_t count[shared::kMaxFluids] = {};
        for (std::size_t i = 0; i < all.size(); ++i) {
            const std::int64_t k = all.fluid[i];
            if (k < 0 || k >= shared::kMaxFluids)
                return makeError("", "particle " + std::to_string(i) + " has fluid index " + std::to_string(k) +
                                         ": expected 0 to " + std::to_string(shared::kMaxFluids - 1) + " (at most " +
                                         std::to_string(shared::kMaxFluids) + " fluids)");
            ++count[k];
        }
        for (int k = 0; k < shared::kMaxFluids; ++k)
            if (count[k] > 0) {
                groups.emplace_back();
                groups.back().fluid = k;
                groups.back().indices.reserve(count[k]);
            }
        int slot[shared::kMaxFluids] = {};
        for (std::size_t g = 0; g < groups.size(); ++g) slot[groups[g].fluid] = int(g);
        for (std::size_t i = 0; i < all.size(); ++i) groups[std::size_t(slot[all.fluid[i]])].indices.push_back(std::uint32_t(i));
        // Only several fluids need their own copies.
        if (groups.size() > 1)
            for (Group& g : groups) g.particles.gather(all, g.indices);
        return okStatus();
    }
};

// The host's side of a frame: what the Host stages of the list
// (render/stages.cpp) make of the particles before the images, and the
// buffers the Renderer keeps for them from frame to frame.
struct HostFrame {
    // Kept between frames (their memory).
    std::vector<glm::vec3> gathered;     // positions of a strided view, made contiguous for the backend
    SpraySplit spray;                    // the body of water and the drops, with the spray on
    FluidSplit fluids;                   // the fluids, when the particles carry a fluid index
    std::vector<Ellipsoids> ellipsoids;  // drawn shapes: one set per fluid drawn (centres: anisotropy only)
    std::vector<float> radii;            // one fluid's own radii, contiguous
    std::vector<SphField> fields;        // with the ray cast: one per fluid drawn
    // The environment map's irradiance coefficients (shared/environment.h),
    // projected once per map and rotation: the map they belong to (held, so
    // that no other map takes its address) and its rotation in turns.
    std::shared_ptr<const EnvironmentImage> irradianceMap;
    float irradianceRotation = 0.0f;
    glm::vec3 irradiance[9] = {};
    // This frame's.
    const ParticleView* particles = nullptr;  // the body of water (every particle without the spray)
    std::span<const glm::vec3> positions;     // its positions, contiguous (anisotropy, one fluid: the smoothed centres)
    bool several = false;                     // several fluids
    bool ownRadii = false;                    // each particle drawn at its own radius
    bool shaped = false;                      // drawn as shapes (anisotropy, own radii or the ray cast)
    bool deviceAnisotropy = false;            // the backend can make the ellipsoids (GL) for one fluid
    bool shapesOnDevice = false;              // it makes this frame's (h.radii: the own radii)
    std::vector<StageTime> times;             // the host stages' times, in their order

    void begin(const ParticleView& all) {
        particles = &all;
        positions = {};
        several = ownRadii = shaped = shapesOnDevice = false;
        times.clear();
    }
};

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
}  // namespace

// spray-classify: the particles split into the body of water, which the
// stages after it see, and the drops (with the diffuse layer's); on the host
// for both backends (the density estimate, the split).
Status hostSprayClassify(HostRun& r) {
    const auto t0 = Clock::now();
    HostFrame& h = r.host;
    const RenderSettings& s = r.settings;
    if (s.spray.enabled) {
        h.spray.split(r.all, s);
        h.particles = &h.spray.body.view;
    } else {
        h.spray.dropPositions.clear(), h.spray.dropVelocities.clear();
    }
    h.spray.addDiffuse(s.diffuse, s.camera, s.radiusM);
    h.times.push_back({"spray-classify", msSince(t0)});
    return okStatus();
}

// fluid-split: the body of water grouped by fluid index
// (docs/pipeline.md#several-fluids), its positions made one contiguous
// array for the backends (the caller's own when the view is one, else
// gathered), and the particles' own radii checked.
Status hostFluidSplit(HostRun& r) {
    HostFrame& h = r.host;
    const RenderSettings& s = r.settings;
    const ParticleView& particles = *h.particles;
    if (auto st = h.fluids.split(particles); !st) return st;
    const std::vector<FluidSplit::Group>& groups = h.fluids.groups;
    h.several = groups.size() > 1;
    if (h.several)  // (one fluid was checked before the stages)
        if (auto st = checkFrameMemory(s.camera.width, s.camera.height, availableMemory(), s.noise.enabled,
                                       s.whitening.enabled, int(groups.size()), s.colorOnly);
            !st)
            return st;
    if (h.several && s.mesh)
        return makeError("", "several fluids are drawn by the screen-space surface, not the mesh path");
    if (s.view == View::FluidId && groups.empty())
        return makeError("", "the fluid-id view needs a fluid index per particle (ParticleView::fluid)");
    const std::byte* first = particles.positions.data;
    if (particles.positions.contiguous() && reinterpret_cast<std::uintptr_t>(first) % alignof(glm::vec3) == 0) {
        h.positions = {reinterpret_cast<const glm::vec3*>(first), particles.size()};
    } else {
        h.gathered.resize(particles.size());
        for (std::size_t i = 0; i < h.gathered.size(); ++i) h.gathered[i] = particles.positions[i];
        h.positions = h.gathered;
    }
    h.ownRadii = s.particleRadii && particles.radius.present();
    if (h.ownRadii)
        for (std::size_t i = 0; i < particles.size(); ++i)
            if (const Status st = checkRadius(particles.radius[i]); !st)
                return makeError("", "particle " + std::to_string(i) + " has radius " +
                                         std::to_string(particles.radius[i]) + " m: " + st.error().message);
    return okStatus();
}

// sph-field: the ray cast's SPH field of each fluid's own positions (the
// centres' smoothing is the splat's only).
Status hostSphField(HostRun& r) {
    const auto t0 = Clock::now();
    HostFrame& h = r.host;
    const std::vector<FluidSplit::Group>& groups = h.fluids.groups;
    h.fields.resize(h.several ? groups.size() : 1);
    for (std::size_t l = 0; l < h.fields.size(); ++l)
        buildSphField(h.several ? std::span<const glm::vec3>(groups[l].particles.positions) : h.positions,
                      r.settings.radiusM, r.settings.raycast, h.fields[l]);
    h.times.push_back({"sph-field", msSince(t0)});
    return okStatus();
}

// anisotropy: each fluid's shapes: with anisotropic kernels (Yu & Turk 2013)
// its ellipsoids and smoothed centres, else spheres of the particles' own
// radii (or of the radius); the ray cast's rays start on (and only where)
// shapes coverRadii times larger. Timed as the anisotropy when it is on.
Status hostShapes(HostRun& r) {
    HostFrame& h = r.host;
    const RenderSettings& s = r.settings;
    const bool anisotropic = s.anisotropy.enabled, raycast = s.raycast.enabled;
    h.shaped = anisotropic || h.ownRadii || raycast;
    if (!h.shaped) return okStatus();
    const auto t0 = Clock::now();
    const std::vector<FluidSplit::Group>& groups = h.fluids.groups;
    h.ellipsoids.resize(h.several ? groups.size() : 1);
    for (std::size_t l = 0; l < h.ellipsoids.size(); ++l) {
        const ParticleView& view = h.several ? groups[l].particles.view : *h.particles;
        const std::span<const glm::vec3> pos =
            h.several ? std::span<const glm::vec3>(groups[l].particles.positions) : h.positions;
        Ellipsoids& e = h.ellipsoids[l];
        h.radii.clear();
        if (h.ownRadii)
            for (std::size_t i = 0; i < view.size(); ++i) h.radii.push_back(view.radius[i]);
        if (anisotropic && h.deviceAnisotropy && !h.several) {
            // The GL backend makes the ellipsoids and the smoothed centres
            // from the positions (gl/anisotropy.h): nothing more here.
            e.centres.clear();
            e.shapes.clear();
            h.shapesOnDevice = true;
            h.times.push_back({"host: anisotropy", msSince(t0)});
            return okStatus();
        }
        if (anisotropic) {
            computeAnisotropy(pos, s.radiusM, s.anisotropy, e, h.radii);
        } else {
            e.centres.clear();
            e.shapes.resize(h.ownRadii ? h.radii.size() : pos.size());
            for (std::size_t i = 0; i < e.shapes.size(); ++i)
                e.shapes[i] = sphereShape(h.ownRadii ? h.radii[i] : s.radiusM);
        }
        if (raycast)
            for (EllipsoidShape& shape : e.shapes) shape = scaledShape(shape, s.raycast.coverRadii);
    }
    if (anisotropic) {
        h.times.push_back({"anisotropy", msSince(t0)});
        if (!h.several) h.positions = h.ellipsoids[0].centres;
    }
    return okStatus();
}

void Renderer::prepareNoise(const ParticleView& particles, const RenderSettings& s) {
    const std::size_t n = particles.size();
    noiseIdz_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        noiseIdz_[i] = shared::noiseIdCoordinate(particles.id.present() ? particles.id[i] : std::int64_t(i));
    // Turbulence needs the particles matched by id between frames and their velocities.
    if (!particles.id.present() || !particles.velocity.present() || s.frameIndex < 0) {
        noiseAmplitude_.clear();
        turbulenceFrame_ = -1;
        return;
    }
    if (s.frameIndex == turbulenceFrame_ && noiseAmplitude_.size() == n) return;  // a redraw of the same frame
    const TurbulenceParams& t = s.noise.turbulence;
    if (!turbulence_ || !(turbulence_->params() == t)) {
        turbulence_ = std::make_unique<TurbulenceTracker>(t);
        turbulenceFrame_ = -1;
    }
    if (turbulenceFrame_ < 0 || s.frameIndex != turbulenceFrame_ + 1) turbulence_->reset();
    std::vector<std::int64_t> ids(n);
    std::vector<glm::vec3> velocities(n);
    for (std::size_t i = 0; i < n; ++i) {
        ids[i] = particles.id[i];
        velocities[i] = particles.velocity[i];
    }
    noiseAmplitude_ = turbulence_->update(ids, velocities);
    turbulenceFrame_ = s.frameIndex;
}

Renderer::Renderer() : backend_(makeCpuBackend()) {}
Renderer::Renderer(std::unique_ptr<Backend> backend) : backend_(std::move(backend)) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Result<Renderer> Renderer::create(BackendChoice choice, std::string* note) {
    return guarded("creating the renderer", [&]() -> Result<Renderer> {
        auto b = makeBackend(choice, note);
        if (!b) return b.error();
        return Renderer(std::move(*b));
    });
}

Result<Renderer> Renderer::createOnCurrentGlContext() {
    return guarded("creating the renderer", [&]() -> Result<Renderer> {
        auto b = makeGlBackendOnCurrentContext();
        if (!b) return b.error();
        return Renderer(std::move(*b));
    });
}

std::string Renderer::backendName() const { return backend_->name(); }

namespace {
// What the particles of a host's GL buffer cannot feed: the stages that read
// the particles on the CPU (RenderSettings named, so the host knows what to
// turn off), and shadows without the box they are framed on.
Status checkHostParticleSettings(const HostParticleBuffer& p, const RenderSettings& s) {
    const char* what = "the host's particle buffer";
    const char* needsHost = s.spray.enabled       ? "the spray (spray.enabled)"
                            : s.noise.enabled     ? "the surface noise (noise.enabled)"
                            : s.whitening.enabled ? "the velocity whitening (whitening.enabled)"
                            : s.raycast.enabled   ? "the ray-cast surface (raycast.enabled)"
                            : s.mesh              ? "the mesh path (mesh)"
                                                  : nullptr;
    if (needsHost)
        return makeError(what, std::string(needsHost) +
                                   " reads the particles on the CPU: pass them as a ParticleView, or turn it off");
    if (drawsShadows(s) && p.bounds.empty() && s.scene.studioBounds.empty())
        return makeError(what, "shadows are drawn: HostParticleBuffer::bounds must give the box holding the particles");
    return okStatus();
}
}  // namespace

Status Renderer::runStages(const ParticleView& all, const RenderSettings& s, std::vector<StageTime>* timings) {
    if (auto st = validateCamera(s.camera); !st) return st.error();
    if (auto st = checkRadius(s.radiusM); !st) return st;
    if (auto st = checkFrameMemory(s.camera.width, s.camera.height, availableMemory(), s.noise.enabled,
                                   s.whitening.enabled, 1, s.colorOnly);
        !st)
        return st;
    if (auto st = all.validate(); !st) return st;
    if (hostParticles_)
        if (auto st = checkHostParticleSettings(*hostParticles_, s); !st) return st;
    const std::size_t particleCount = hostParticles_ ? hostParticles_->count : all.size();
    if (auto st = checkRenderMemory(particleCount,
                                    renderBytesPerParticle(all, s.anisotropy.enabled, s.raycast.enabled, s.noise.enabled),
                                    s.camera.width, s.camera.height,
                                    frameBytes(s.camera.width, s.camera.height, s.noise.enabled, s.whitening.enabled,
                                               1, s.colorOnly));
        !st)
        return st;
    if (s.mesh)
        if (auto st = checkMesh(*s.mesh); !st) return st;
    if (s.scene.backdrop)
        if (auto st = checkBackdropSize(*s.scene.backdrop, s.camera.width, s.camera.height); !st) return st;
    // Each stage's parameters, and what the view needs of them (render/stages.cpp).
    if (auto st = checkStages(s); !st) return st;
    const int divisor = fluidDivisor(s.fluidScale);
    const bool drops = drawsDrops(s);
    if (s.compositor)
        if (auto st = checkSortLast(s, all); !st) return st;
    // The studio is built around every particle, spray included.
    Bounds box = s.scene.studioBounds;
    if (box.empty()) {
        for (std::size_t i = 0; i < all.size(); ++i) box.extend(all.positions[i]);
        if (hostParticles_ && !hostParticles_->bounds.empty()) {
            box.extend(hostParticles_->bounds.min);
            box.extend(hostParticles_->bounds.max);
        }
        // And around the scene's objects: the floor under the tank, not inside it.
        if (s.geometry)
            if (const Bounds g = s.geometry->bounds(); !g.empty()) {
                box.extend(g.min);
                box.extend(g.max);
            }
    }
    // The host's stages (render/stages.cpp): the spray's split, the fluids,
    // the ray cast's field, the shapes.
    if (!host_) host_ = std::make_unique<HostFrame>();
    HostFrame& h = *host_;
    h.begin(all);
    // The GL backend makes the ellipsoids of one fluid itself on a hardware
    // GPU; not for sort-last, whose shares splat slices of the shapes the
    // host made, and not on Mesa's llvmpipe, which runs the GPU's neighbour
    // walk 2-3x slower than the host's loop (docs/performance.md).
    // MENISCUS_GL_HOST_ANISOTROPY=1 takes the host's (bit for bit the CPU
    // backend's: the GL parity tests of the stages after it), =0 the GPU's
    // (llvmpipe too: the tests of the GL passes).
    const char* hostAnisotropy = std::getenv("MENISCUS_GL_HOST_ANISOTROPY");
    const bool gpuAnisotropy = hostAnisotropy && *hostAnisotropy
                                   ? std::string_view(hostAnisotropy) == "0"
                                   : backend_->name().find("llvmpipe") == std::string::npos;
    // The host's own particle buffer never comes to the host: the GPU's, always.
    h.deviceAnisotropy = backend_->kind() == BackendKind::Gl && !s.compositor && (gpuAnisotropy || hostParticles_);
    HostRun hostRun{s, all, h};
    if (auto st = runHostStages(StageWhen{s}, hostRun); !st) return st;
    const ParticleView& particles = *h.particles;
    const std::vector<FluidSplit::Group>& groups = h.fluids.groups;
    const bool several = h.several, shaped = h.shaped;
    const bool anisotropic = s.anisotropy.enabled, raycast = s.raycast.enabled;
    std::span<const glm::vec3> positions = h.positions;
    // Fluid k's material.
    auto shadingOf = [&](int k) {
        ShadingParams sh = s.shading;
        if (k >= 0 && std::size_t(k) < s.fluidMaterials.size()) sh.material = s.fluidMaterials[std::size_t(k)];
        return sh;
    };
    FrameSettings f;
    static_cast<StageParams&>(f) = s;  // every stage's parameters, whole
    f.camera = s.camera;
    f.radius = s.radiusM;
    if (shaped && !several) f.shapes = h.ellipsoids[0].shapes;
    if (h.shapesOnDevice) {
        f.deviceAnisotropy = &s.anisotropy;
        f.deviceRadii = h.radii;
        f.deviceShapeScale = raycast ? s.raycast.coverRadii : 1.0f;
    }
    f.timed = timings != nullptr;
    if (raycast) {
        if (!several) f.field = &h.fields[0];
        // The larger shapes' chords, calibrated as spheres of coverRadii r at
        // the same spacing (shared::thicknessWeight): the same thickness.
        const float spacing = s.thickness.spacingM > 0.0f ? s.thickness.spacingM : 2.0f * s.radiusM;
        f.thickness.spacingM = spacing / s.raycast.coverRadii;
    }
    f.shading = shadingOf(groups.size() == 1 ? groups[0].fluid : -1);
    f.particles = particles;
    f.mesh = s.mesh;
    f.geometry = s.geometry;
    if (s.noise.enabled) {
        prepareNoise(particles, s);
        f.noiseIdz = noiseIdz_;
        f.noiseAmplitude = noiseAmplitude_;
    }
    if (s.whitening.enabled) {
        whiteness_.assign(particles.size(), 0.0f);
        if (particles.velocity.present())
            for (std::size_t i = 0; i < whiteness_.size(); ++i)
                whiteness_[i] = shared::whitenessOfSpeed(glm::length(particles.velocity[i]), s.whitening.thresholdMps,
                                                         s.whitening.rampMps);
        f.whiteness = whiteness_;
    }
    if (drops) {
        f.sprayPositions = h.spray.dropPositions;
        f.sprayVelocities = h.spray.dropVelocities;
    }
    f.studio = shared::makeStudio(box, s.radiusM, s.camera, s.scene, s.shading.lightDirWorld);
    f.backdrop = s.scene.backdrop;
    f.hostLayers = embed_;
    f.hostParticles = hostParticles_;
    f.environment = {};
    f.environmentImage = s.scene.environment;
    if (s.scene.environment && !s.scene.environment->rgb.empty()) {
        f.environment.texels = s.scene.environment->rgb.data();
        f.environment.width = s.scene.environment->width;
        f.environment.height = s.scene.environment->height;
        f.environment.rotation = s.scene.environmentRotationDeg / 360.0f;
        f.environment.intensity = s.scene.environmentIntensity;
        // The ambient light from the map (docs/pipeline.md#environment-map):
        // projected when the map or its rotation changes, scaled per frame.
        if (h.irradianceMap != s.scene.environment || h.irradianceRotation != f.environment.rotation) {
            shared::environmentIrradianceSh(f.environment.texels, f.environment.width, f.environment.height,
                                            f.environment.rotation, 1.0f, h.irradiance);
            h.irradianceMap = s.scene.environment;
            h.irradianceRotation = f.environment.rotation;
        }
        for (int k = 0; k < 9; ++k) f.environment.irradiance[k] = h.irradiance[k] * f.environment.intensity;
    }
    if (drawsShadows(s)) f.shadow = shadowLight(f);
    f.fluidDivisor = divisor;
    f.upsampleJumpM = defaults::kDepthJumpRadii * s.radiusM;
    f.compositor = s.compositor;
    // Sort-last over the whole frame (RenderSettings::share): the kernels,
    // the spray's split and the noise's inputs above saw every particle; this
    // process splats its share of them (of the body, with the spray on: the
    // kept particles of the share, a contiguous run of the body). With the
    // noise or the whitening, which splat every particle again after the
    // composite (on the root), the backend gets all and splats its range.
    if (s.compositor && s.share) {
        ParticleRange r = *s.share;
        if (s.spray.enabled) {
            const std::vector<std::uint32_t>& kept = h.spray.kept;
            r.begin = std::size_t(std::lower_bound(kept.begin(), kept.end(), std::uint32_t(s.share->begin)) - kept.begin());
            r.end = std::size_t(std::lower_bound(kept.begin(), kept.end(), std::uint32_t(s.share->end)) - kept.begin());
        }
        if (s.noise.enabled || s.whitening.enabled) {
            if (backend_->name() != "cpu")
                return makeError("", "RenderSettings::share with the noise or the whitening: sort-last composites "
                                     "these on the CPU backend only");
            f.splatRange = r;
        } else {
            positions = positions.subspan(r.begin, r.end - r.begin);
            if (!f.shapes.empty()) f.shapes = f.shapes.subspan(r.begin, r.end - r.begin);
            f.particles = sliceView(particles, r.begin, r.end - r.begin);
        }
    }
    Backend& b = *backend_;
    // The stages' drivers made ready once per backend (GL: their programs).
    if (!prepared_) {
        if (auto st = prepareStages(b); !st) return st;
        prepared_ = true;
    }
    if (auto st = b.beginFrame(positions, f); !st) return st.error();

    // The stages, in the order of their list (render/stages.cpp), scope by
    // scope: the scene; each surface (the one fluid, or each fluid's layer)
    // at the splat's resolution, then at full resolution; then the passes
    // over the whole picture. After each stage the backend says whether it
    // failed (GL: a GL error, out of GPU memory, a lost context), and the
    // frame stops there with an error naming the stage. Timing brackets only
    // when asked for (on GL they wait for the GPU).
    const StageWhen when{s, several};
    const bool timed = timings != nullptr;
    StageRun r{b, s, f, divisor > 1 ? reducedCamera(s.camera, divisor) : s.camera, {}, {}, {}, false, {}};
    if (auto st = runScope(StageScope::Frame, when, r, timed); !st) return st;
    for (std::size_t l = 0; l < (several ? groups.size() : 1); ++l) {
        StageSlots q;  // the full image's
        if (several) {
            // Several fluids (docs/pipeline.md#several-fluids): each drawn and
            // shaded on its own into its layer's images (at reduced resolution:
            // upsampled, shaded, its edges blended, E and T with them), then
            // composited front to back.
            FluidSplit::Group& g = h.fluids.groups[l];
            auto layer = [l](LayerImage what) { return layerSlot(int(l), what); };
            const std::span<const float> none;
            gatherValues(s.noise.enabled ? f.noiseIdz : none, g.indices, g.idz);
            gatherValues(s.noise.enabled ? f.noiseAmplitude : none, g.indices, g.amplitude);
            gatherValues(s.whitening.enabled ? f.whiteness : none, g.indices, g.whiteness);
            const std::span<const glm::vec3> centres =
                anisotropic ? std::span<const glm::vec3>(h.ellipsoids[l].centres) : g.particles.positions;
            const std::span<const EllipsoidShape> shapes =
                shaped ? std::span<const EllipsoidShape>(h.ellipsoids[l].shapes) : std::span<const EllipsoidShape>();
            b.setFluid(centres, {g.particles.view, shapes, raycast ? &h.fields[l] : nullptr, shadingOf(g.fluid), g.idz,
                                 g.amplitude, g.whiteness});
            r.tag = "fluid " + std::to_string(g.fluid) + ": ";
            q.raw = layer(LayerImage::RawDepth), q.thickness = layer(LayerImage::Thickness);
            q.depth = layer(LayerImage::Depth), q.normal = layer(LayerImage::Normal);
            q.noise = layer(LayerImage::Noise), q.whitening = layer(LayerImage::Whitening);
            q.color = layer(LayerImage::Color), q.emission = layer(LayerImage::Emission);
            q.transmit = layer(LayerImage::Transmit);
            r.fluidOfLayer.push_back(g.fluid);
        }
        r.io.at = q;
        if (divisor > 1) {
            // Reduced resolution (docs/pipeline.md#reduced-resolution): the
            // surface on the low camera in the Low* slots (raw depth in q.raw),
            // upsampled into the full-size q.
            b.setCamera(r.splatCamera);
            r.io.at.sceneDepth = Slot::LowSceneDepth, r.io.at.thickness = Slot::LowThickness;
            r.io.at.depth = Slot::LowDepth, r.io.at.normal = Slot::LowNormal, r.io.at.noise = Slot::LowNoise;
        }
        if (auto st = runScope(StageScope::Surface, when, r, timed); !st || r.handedOver) return st;
        if (divisor > 1) b.setCamera(s.camera);
        r.io.at = q;
        if (auto st = runScope(StageScope::Layer, when, r, timed); !st) return st;
    }
    r.tag.clear();
    r.io.at = StageSlots{};
    return runScope(StageScope::Finish, when, r, timed);
}

Drawn Renderer::drawn(const RenderSettings& s) const {
    Drawn d{s.noise.enabled, s.whitening.enabled, drawsDrops(s), s.silhouette.enabled, {}, -1};
    const std::vector<FluidSplit::Group> none;
    const std::vector<FluidSplit::Group>& groups = host_ ? host_->fluids.groups : none;
    if (groups.size() > 1)
        for (const FluidSplit::Group& g : groups) d.layerFluids.push_back(g.fluid);
    if (groups.size() == 1) d.singleFluid = groups[0].fluid;
    return d;
}

Result<Aovs> Renderer::render(const ParticleView& particles, const RenderSettings& s,
                              std::vector<StageTime>* timings) {
    return guarded("rendering", [&]() -> Result<Aovs> {
        if (auto st = runStages(particles, s, timings); !st) return st.error();
        Backend& b = *backend_;
        auto hostTimes = [&] { collectTimes(*timings); };
        // Sort-last, not the root: the frame ended after the composite.
        if (s.compositor && !s.compositor->root()) {
            if (timings) hostTimes();
            return Aovs{};
        }
        const auto t0 = std::chrono::steady_clock::now();
        Aovs aovs = readAovs(b, s.view, s.colorOnly, s.noise, drawn(s));
        rawDepthAtFullSize(s, aovs);
        if (auto st = b.stageStatus("readback"); !st) return st.error();
        const double readMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (timings) {
            hostTimes();
            if (b.name() != "cpu") timings->push_back({"readback", readMs});  // GPU -> host copies of the AOVs read
        }
        applyView(s.view, s.colorOnly, aovs);
        return aovs;
    });
}

void Renderer::collectTimes(std::vector<StageTime>& timings) {
    // The host's own stages (not the backend's), first in the list.
    timings = backend_->stageTimes();
    if (host_) timings.insert(timings.begin(), host_->times.begin(), host_->times.end());
}

Status Renderer::draw(const ParticleView& particles, const RenderSettings& s, std::vector<StageTime>* timings) {
    return guarded("drawing", [&]() -> Status {
        if (auto st = runStages(particles, s, timings); !st) return st;
        if (timings) collectTimes(*timings);
        if (s.compositor && !s.compositor->root()) return okStatus();  // sort-last: ended after the composite
        if (s.view == View::Final) return okStatus();  // the colour is already in its slot
        Aovs aovs = readAovs(*backend_, s.view, true, s.noise, drawn(s));
        rawDepthAtFullSize(s, aovs);
        applyView(s.view, true, aovs);
        backend_->writeColor(Slot::Color, std::move(aovs.color));
        return backend_->stageStatus("debug view");
    });
}

Status Renderer::present(int framebufferWidth, int framebufferHeight, int left) {
    return guarded("presenting", [&]() -> Status {
        return backend_->present(Slot::Color, {framebufferWidth, framebufferHeight, left, false, true});
    });
}

Status Renderer::drawIntoHost(const ParticleView& particles, const RenderSettings& settings, const HostLayers& host,
                              std::vector<StageTime>* timings) {
    return guarded("drawing into the host's frame",
                   [&]() -> Status { return drawIntoHostWith(particles, settings, host, timings); });
}

Status Renderer::drawIntoHost(const HostParticleBuffer& particles, const RenderSettings& settings,
                              const HostLayers& host, std::vector<StageTime>* timings) {
    return guarded("drawing into the host's frame", [&]() -> Status {
        hostParticles_ = &particles;
        struct Release {
            const HostParticleBuffer*& particles;
            ~Release() { particles = nullptr; }
        } release{hostParticles_};
        return drawIntoHostWith(ParticleView{}, settings, host, timings);
    });
}

Status Renderer::drawIntoHostWith(const ParticleView& particles, const RenderSettings& settings,
                                  const HostLayers& host, std::vector<StageTime>* timings) {
    const char* what = "the host's layers";
    if (backend_->kind() != BackendKind::Gl)
        return makeError(what, "drawing into a host's frame needs a GL renderer (Renderer::createOnCurrentGlContext)");
    if (host.colorTexture == 0 || host.depthTexture == 0)
        return makeError(what, "both a colour and a depth texture are needed");
    if (settings.scene.backdrop) return makeError(what, "a backdrop and a host's frame cannot both be the scene");
    if (settings.compositor) return makeError(what, "sort-last rendering does not draw into a host's frame");
    auto camera = cameraFromGlMatrices(host.view, host.projection, host.width, host.height);
    if (!camera) return camera.error();
    RenderSettings s = settings;
    s.camera = *camera;
    s.view = View::Final;
    embed_ = &host;
    struct Release {
        const HostLayers*& embed;
        ~Release() { embed = nullptr; }
    } release{embed_};
    if (auto st = runStages(particles, s, timings); !st) return st;
    if (timings) collectTimes(*timings);
    if (auto st = backend_->present(Slot::Color, {host.width, host.height, 0, true, host.colorIsSrgb}); !st)
        return st;
    return backend_->stageStatus("drawing into the host's frame");
}

Result<Aovs> renderFrame(const ParticleView& particles, const RenderSettings& settings,
                         std::vector<StageTime>* timings) {
    return guarded("rendering", [&]() -> Result<Aovs> { return Renderer().render(particles, settings, timings); });
}

}  // namespace meniscus
