// Every user-facing parameter and default lives here (and only here), with its
// unit. Lengths given "in radii" are multiples of the particle radius r and
// pixel sizes are derived from the real camera (projected radius r*f/z), so
// every stage is scale-invariant: scaling particles, radius and camera by s
// changes nothing in the image.
#pragma once

#include <memory>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include <glm/glm.hpp>

#include "meniscus/backdrop.h"
#include "meniscus/environment.h"
#include "meniscus/types.h"

namespace meniscus {

// The isosurface path's field (docs/surface.md), declared before its default.
// The scalar field whose level set is the surface. Both are normalised so that
// 1 is the value inside fluid at rest (the interior of a simple cubic lattice
// of spacing 2r, as SPlisHSPlasH and DualSPHysics sample a fluid); the iso
// level is a fraction of that.
enum class SurfaceField {
    // Thesis eq. 4.16: f(d) = (d/(sqrt2 Rc))^4 - (d/(sqrt2 Rc))^2 + 1/4 for
    // d < Rc (a metaball falloff), summed over the particles.
    Thesis,
    // The SPH density with the cubic-spline kernel (Monaghan 1992) of support
    // h = 4r: exactly the surface refsurf, the reference ray tracer of the
    // true SPH surface (docs/quality.md), traces.
    Sph,
};

namespace defaults {

inline constexpr int kWidth = 1280;           // pixels
inline constexpr int kHeight = 720;           // pixels
inline constexpr int kMaxImageSizePx = 16384;  // the largest width or height (CLI and validateCamera)
inline constexpr float kFovYDegrees = 40.0f;  // vertical field of view (Camera's default, the auto camera's)
inline constexpr float kNearM = 0.01f;        // metres
inline constexpr float kFarM = 1000.0f;       // metres

// The CLI's default smoothing filter and material (names as filterFromName
// and materialPreset take them).
inline constexpr const char* kFilterName = "narrow-range";
inline constexpr const char* kMaterialName = "water";

// Auto-framing: the view direction from the target toward the eye, as azimuth
// around +y (0 = +z, positive toward +x) and elevation above the horizon.
inline constexpr float kAutoAzimuthDegrees = 35.0f;
inline constexpr float kAutoElevationDegrees = 25.0f;
// Fraction of the half-image the framed particles may fill (1 = touch the edges).
inline constexpr float kAutoFill = 0.9f;
// Fraction of particles (the outermost, e.g. lone spray) the auto camera may leave out.
inline constexpr float kAutoOutlierFraction = 0.001f;
// At most about this many points decide the auto camera (an even stride through the set).
inline constexpr int kAutoFramePoints = 50000;
// A sequence is framed from this many frames evenly spaced from the first to
// the last (fewer when it is shorter), about kSequenceFramePoints points each.
inline constexpr int kSequenceFramingFrames = 5;
inline constexpr int kSequenceFramePoints = 20000;

// A file's SPH smoothing length h gives each particle the radius
// h / (2 k), k = kHPerSpacing: h in particle spacings (2 r). The codes name k
// hdx (PySPH, 1.0-1.3 in its examples), d0_multiplier (Chrono, 1.2) or take
// h = coefh sqrt(3) dp (DualSPHysics, about 1.7 for coefh 1); --h-per-spacing.
inline constexpr float kHPerSpacing = 1.2f;

// Movies (include/meniscus/video.h): frames per second, and x264's constant
// rate factor (0 lossless .. 51; 18 is about visually lossless, x264's own
// default 23 shows blocking in the liquid's smooth gradients).
inline constexpr double kVideoFps = 30.0;
inline constexpr int kVideoCrf = 18;

// A depth step between neighbouring pixels larger than this many radii is a
// discontinuity (silhouette / separate body): filters and normals never
// difference or average across it.
inline constexpr float kDepthJumpRadii = 5.0f;

// Reduced-resolution processing (docs/pipeline.md#reduced-resolution): the
// fraction of the image's width and height the splat, smoothing, normals and
// noise run at: 1 (full resolution, the default), 0.5 or 0.25. Upsampled
// depth-aware for shading.
inline constexpr float kFluidScale = 1.0f;

// Kernel radii in pixels are capped here (cost bound for near fluid).
inline constexpr int kMaxKernelPx = 32;


// The isosurface path (include/meniscus/surface.h).
inline constexpr SurfaceField kSurfaceField = SurfaceField::Sph;
inline constexpr float kCubeSizeRadii = 0.5f;     // marching-cubes cube edge, particle radii
inline constexpr float kSurfaceIso = 0.5f;        // fraction of the rest value (see SurfaceField)
inline constexpr float kThesisSupportRadii = 2.5f;  // Rc of the thesis field, particle radii
inline constexpr float kSphSupportRadii = 4.0f;     // h of the cubic spline, particle radii (refsurf's)
inline constexpr int kBlockCubes = 32;            // a block is n x n x n cubes

// The simulator (include/meniscus/sim.h). Tolerances and CFL factor are
// SPlisHSPlasH 2.16's defaults, so the bench compares like with like.
inline constexpr float kSimRadiusM = 0.025f;           // particle radius, metres (SPlisHSPlasH's default)
inline constexpr float kSimRestDensity = 1000.0f;      // kg/m^3, water
inline constexpr float kSimGravity = 9.81f;            // m/s^2, along -y
inline constexpr float kSimViscosity = 1e-6f;          // DFSPH: kinematic viscosity, m^2/s (water; SPlisHSPlasH's dam break sets 0.01)
inline constexpr float kSimSphStiffness = 1000.0f;     // Muller SPH: k, m^2/s^2 (speed of sound^2)
inline constexpr float kSimCfl = 1.0f;                 // CFL factor
inline constexpr float kSimMinDtS = 1e-5f;             // s
inline constexpr float kSimMaxDtS = 0.005f;            // s
inline constexpr float kSimDensityTolerance = 0.0005f; // 0.05 % of rho0, mean
inline constexpr float kSimDivergenceTolerance = 0.001f; // 0.1 % of rho0 per time step, mean
inline constexpr int kSimMaxIterations = 100;          // per DFSPH solver per step
inline constexpr float kSimWallNearestRadii = 0.5f;   // DFSPH: walls are evaluated no closer than this, particle radii
inline constexpr int kSimResortEvery = 50;             // steps between z-order re-sorts
inline constexpr double kSimFps = 25.0;                // frames per simulated second written
}  // namespace defaults

// ---- Smoothing filters (docs/pipeline.md#smoothing) -------------------------

struct NoFilter {};

// Separable Gaussian; sigma is constant in world space (projected per pixel).
struct GaussianParams {
    int iterations = 2;
    float sigmaRadii = 2.0f;                 // spatial sigma, radii; kernel radius = 3 sigma
    float jumpRadii = defaults::kDepthJumpRadii;
    int maxKernelPx = defaults::kMaxKernelPx;
};

// Separable bilateral (thesis eq. 4.1-4.3, Pham & van Vliet 2005).
struct BilateralParams {
    int iterations = 2;
    float sigmaRadii = 2.0f;                 // spatial sigma, radii; kernel radius = 3 sigma
    float rangeSigmaRadii = 3.0f;            // depth-difference sigma, radii
    float jumpRadii = defaults::kDepthJumpRadii;
    int maxKernelPx = defaults::kMaxKernelPx;
};

// Separable binomial (Instant Liquids §2.2): kernel half-size = projected splat radius.
struct BinomialParams {
    int iterations = 4;
    float sizeRadii = 2.0f;                  // kernel half-size, radii
    float jumpRadii = defaults::kDepthJumpRadii;
    int maxKernelPx = defaults::kMaxKernelPx;
};

// Screen-space curvature flow (van der Laan et al. 2009;
// docs/pipeline.md#curvature-flow).
struct CurvatureFlowParams {
    int iterations = 40;
    float alpha = 0.4f;                      // time step dt = alpha * z / f (stable below 0.5)
    float jumpRadii = defaults::kDepthJumpRadii;
};

// Narrow-range filter (Truong & Yuksel, I3D 2018;
// docs/pipeline.md#narrow-range-filter).
struct NarrowRangeParams {
    int iterations = 1;                      // one: with the anisotropic kernels (the default) it scored best (docs/quality.md)
    float filterSizeRadii = 3.0f;            // world kernel radius, radii (sigma = radius / 3)
    float lambda = 10.0f;                    // range threshold tau = lambda * r
    float mu = 1.0f;                         // taps behind the range count as z0 + mu * r
    int maxKernelPx = defaults::kMaxKernelPx;
    bool separable = false;                  // 1-D x then y approximation
};

using FilterParams =
    std::variant<NoFilter, GaussianParams, BilateralParams, BinomialParams, CurvatureFlowParams, NarrowRangeParams>;

// CLI names: none, gaussian, bilateral, binomial, curvature-flow, narrow-range.
// filterFromName returns false for an unknown name.
bool filterFromName(const std::string& name, FilterParams* out);
std::string filterName(const FilterParams& filter);
std::string filterNames();  // comma separated, for --help
int filterIterations(const FilterParams& filter);  // 0 for none
void setFilterIterations(FilterParams& filter, int iterations);

// ---- Thickness (docs/pipeline.md#thickness) ---------------------------------

struct ThicknessParams {
    float spacingM = 0.0f;                   // rest spacing s; 0 = 2 r (the radius is half the spacing)
    float blurSigmaRadii = 1.0f;             // Gaussian blur sigma, radii; 0 = no blur
    int resolutionDivisor = 1;               // thickness on a 1/n-resolution grid, then upsampled: 1 = full, 2 = half (4 allowed)
    int maxKernelPx = defaults::kMaxKernelPx;
    // Thin liquid: a fluid pixel is shaded as at least this thick,
    // radii, so the rim of a drop or a sheet one particle thick is tinted as
    // liquid, never drawn as the untinted background. 0 = the thickness as splatted.
    float minRadii = 1.0f;
};

// ---- Hole filling (docs/pipeline.md#hole-filling; src/shared/hole_fill.h) ----

// After the splat, before the smoothing: a pixel left uncovered inside a
// sheet is filled when the liquid of one surface closes it in along the row,
// the column and both diagonals (ends found within reachPx pixels each way,
// at most jumpRadii r apart in depth), and at least three of those lines are
// at most maxSpanRadii r long (a slit may be long one way). It takes the
// lines' mean interpolated depth and thickness. Gaps open to a side (between
// drops, a bay in the outline) and gaps between layers stay.
struct HoleFillParams {
    bool enabled = true;
    float maxSpanRadii = 4.0f;               // widest gap filled, radii (4: two particle diameters)
    float jumpRadii = defaults::kDepthJumpRadii;
    int reachPx = 2 * defaults::kMaxKernelPx;  // search per side, pixels (the length of a slit filled)
    // Passes, each reading the last one's output: where two slits cross,
    // both lines are long until one pass has filled the slits around.
    int passes = 2;
};

// The first parameter out of range, as "field: what is allowed" (the
// thickness floor too); empty when all are fine.
std::string checkHoleFillParams(const HoleFillParams& p, const ThicknessParams& thickness);

// ---- Turbulence, for the surface noise (docs/pipeline.md#noise-and-foam) ----

// A particle whose velocity changed by more than tauMps between two
// consecutive frames of a sequence (|v(t) - v(t-1)| > tau, the particles
// matched by id) gets its noise amplitude multiplied by `boost`; the boost then
// fades linearly back to 1 over holdFrames frames unless the particle is
// turbulent again (turbulent water looks rougher).
struct TurbulenceParams {
    float tauMps = 0.5f;   // velocity change between frames, m/s
    float boost = 3.0f;    // amplitude factor when turbulent (>= 1)
    int holdFrames = 12;   // frames over which the boost fades (>= 1)
    bool operator==(const TurbulenceParams&) const = default;
};

// ---- Surface noise and foam (docs/pipeline.md#noise-and-foam) ---------------

// The NVIDIA SSFR patent's surface noise (US 8,947,430, eqs. 14-17): every
// particle near the surface splats a sprite of fractal Perlin noise (the
// pattern seeded by its id, so it travels with the particle), weighted by how
// far its front lies below the smoothed surface. The sum N(x, y) bumps the
// normals by its gradient and tints the surface with foam by its magnitude.
// Off unless enabled (the CLI's --noise).
struct NoiseParams {
    bool enabled = false;
    float spriteRadii = 2.0f;        // sprite radius, particle radii
    float sigma = 0.4f;              // the sprite's Gaussian sigma, sprite radii (cut at 1)
    float frequency = 1.0f;          // noise cycles per sprite radius, first octave
    int octaves = 3;                 // fractal octaves, 1..6
    float lacunarity = 2.0f;         // frequency factor per octave, 1..4
    float gain = 0.5f;               // amplitude factor per octave, 0..1
    float depthFalloffRadii = 1.0f;  // depth below the surface where the weight is 1/e, radii
    float bump = 0.25f;              // normal perturbation: N as a height of bump sprite radii
    float foamThreshold = 0.3f;      // |N| where foam starts
    float foamGain = 2.5f;           // foam cover per unit of |N| above the threshold (1 = white)
    glm::vec3 foamColor{0.80f, 0.83f, 0.86f};  // linear RGB of lit foam
    TurbulenceParams turbulence;     // rougher noise where velocities jump (needs ids and velocities)
};

// The first parameter out of range, as "field: what is allowed"; empty when all are fine.
std::string checkNoiseParams(const NoiseParams& p);

// ---- Velocity whitening (docs/pipeline.md#noise-and-foam) -------------------

// Instant Liquids' velocity map (Cords & Staadt 2008, §4): fast water is
// aerated and looks whiter. Each particle near the surface splats its
// whiteness clamp((|v| - threshold) / ramp, 0, 1) with the noise's kind of
// sprite (Gaussian, weighted by its depth below the surface); the map is the
// weighted mean, and the shading lays `strength` times that of lit white over
// the liquid. Needs the particles' velocities. Off unless enabled (--whiten).
struct WhiteningParams {
    bool enabled = false;
    float thresholdMps = 2.5f;       // speed where whitening starts, m/s (a dam break's bulk runs at 2-3)
    float rampMps = 2.0f;            // speed range over which it rises to full, m/s (> 0)
    float strength = 0.6f;           // white cover at full whitening, 0..1
    glm::vec3 color{0.86f, 0.89f, 0.92f};  // linear RGB of lit white water
    float spriteRadii = 2.0f;        // sprite radius, particle radii
    float sigma = 0.4f;              // the sprite's Gaussian sigma, sprite radii (cut at 1)
    float depthFalloffRadii = 1.0f;  // depth below the surface where the weight is 1/e, radii
};

// The first parameter out of range, as "field: what is allowed"; empty when all are fine.
std::string checkWhiteningParams(const WhiteningParams& p);

// ---- Spray (docs/pipeline.md#classification, docs/pipeline.md#noise-and-foam) ----

// The NVIDIA patent's spray: particles whose density is below sprayDensity
// times the rest density have left the body of water. They are taken out of
// the surface (splat, thickness, smoothing, noise) and drawn as small lit,
// semi-transparent drops, each stretched along its velocity over a short
// exposure, composited with depth against the surface and the scene. The
// density is the particles' `density` attribute, or an SPH estimate from
// their neighbours when the file has none. Off unless enabled (--spray).
struct SprayParams {
    bool enabled = false;
    float sprayDensity = 0.5f;    // fraction of the rest density below which a particle is spray
    float restDensityKgM3 = 0.0f;  // rest density of the attribute, kg/m^3; 0 = the frame's median density
    float sizeRadii = 0.6f;       // a drop's drawn radius, particle radii
    float streakSeconds = 0.01f;  // exposure: a drop is drawn along its path over this time, s
    float opacity = 0.8f;         // optical depth of a drop at its centre
    glm::vec3 color{0.80f, 0.84f, 0.88f};  // linear RGB of a lit drop
};

// The first parameter out of range, as "field: what is allowed"; empty when all are fine.
std::string checkSprayParams(const SprayParams& p);

// ---- Anisotropic kernels (Yu & Turk, SCA 2010 / TOG 32(1) 2013) ------------

// Each particle is splatted as an ellipsoid instead of a sphere of radius r:
// the principal axes of the weighted covariance of its neighbours within
// neighbourRadii r (weights 1 - (d/R)^3, Yu & Turk eq. 11), the axis lengths
// proportional to the covariance's eigenvalues (their eq. 13), the smaller two
// raised to at least 1/kr of the largest, scaled so the ellipsoid keeps the
// volume of the sphere of radius r (Yu & Turk scale by a constant ks = 1400
// for their units; keeping the volume is what makes the thickness calibration,
// which counts volume, still hold, and is scale-free). A particle with fewer
// than minNeighbours neighbours is a sphere of kn r instead (spray shrinks to
// droplets). The ellipsoids are centred on Laplacian-smoothed positions,
// x' = (1 - smoothing) x + smoothing * (weighted mean of the neighbourhood)
// (Yu & Turk eq. 6, their lambda). In the bulk the covariance is isotropic and
// the ellipsoid is the sphere of radius r; at a free surface it flattens along
// the normal and widens along it, so the splatted surface follows the
// iso-surface instead of a layer of beads, and a one-particle sheet is closed.
// Computed once per frame on the host in O(N) (a hashed grid), threaded, the
// result independent of the thread count. Off unless enabled.
struct AnisotropyParams {
    bool enabled = true;          // on by default: sheets close, spray reads as droplets
    float neighbourRadii = 4.0f;  // R, the neighbourhood radius, particle radii (2 rest spacings)
    float kr = 4.0f;              // largest ratio of the longest axis to the shortest (Yu & Turk's kr)
    float kn = 0.5f;              // a particle with too few neighbours is a sphere of kn r (Yu & Turk's kn)
    int minNeighbours = 8;        // N_eps: fewer neighbours within R (itself not counted) = isolated
    float smoothing = 0.0f;       // lambda of the centres' Laplacian smoothing, 0 (none) .. 1
    // Keep a free surface where the spheres put it: a flattened ellipsoid at
    // the surface moves outward along its shortest axis by r minus that
    // half-axis, scaled by how one-sided its neighbourhood is (0 in the bulk
    // and in a sheet, 1 at a flat face).
    bool keepSurface = true;
};
// Why these values (docs/quality.md has the measurements against refsurf):
// kr = 4 and kn = 0.5 are Yu & Turk's. Within R = 2 rest spacings a particle
// of the bulk has ~33 neighbours, of a flat free surface ~17, of a sheet one
// particle thick ~12, of a filament ~4: N_eps = 8 flattens sheets and
// shrinks filaments and lone drops (Yu & Turk's 25 belongs to their larger
// neighbourhood). R = 2.5 and 3 spacings scored the same or worse and cost
// more; smoothing (their lambda 0.9) moved the splatted surface inward and
// raised the normal error on every camera, so it is off by default.

// The first parameter out of range, as "field: what is allowed"; empty when all are fine.
std::string checkAnisotropyParams(const AnisotropyParams& p);

// ---- The SPH surface, ray cast (docs/pipeline.md#ray-cast-surface) ----------

// Instead of smoothing the splatted depth, every covered pixel's ray is
// marched through the particles' SPH density (the cubic spline of support
// supportRadii r, normalised so 1 = fluid at rest on a lattice of spacing 2r)
// to the first point where it reaches `iso`: the surface the isosurface path
// meshes and refsurf (the reference ray tracer of the true SPH surface,
// docs/quality.md) traces, with its gradient as the
// normal (ray casting of SPH data: Fraedrich, Auer & Westermann, IEEE TVCG
// 16(6), 2010). The splat (spheres of coverRadii r, or the ellipsoids) gives
// each ray its start and decides which pixels are tried; a ray that finds no
// surface within maxSteps steps is no fluid (a lone drop whose own density
// stays below the iso level has no surface). The march steps stepRadii r at
// a time (refsurf's h/4), then a linear interpolation across the step and
// newtonSteps Newton steps on F place the crossing. Off unless enabled (--raycast).
struct RaycastParams {
    bool enabled = false;
    float iso = defaults::kSurfaceIso;                // fraction of the rest density
    float supportRadii = defaults::kSphSupportRadii;  // h, particle radii
    float stepRadii = 1.0f;                           // march step, particle radii
    int maxSteps = 64;                                // steps before a ray gives up
    int newtonSteps = 1;                              // Newton steps after the interpolation
    // The splatted spheres' radius, particle radii: the iso-surface bridges
    // the gaps between particles and so reaches past the spheres of r.
    float coverRadii = 1.5f;
};
// Why these values (docs/quality.md has the measurements): iso 0.5 and h = 4r
// are refsurf's. coverRadii above sqrt 2 closes the gaps a face of a 2r
// lattice leaves between its spheres (a ray through one would find no start);
// on frame 21 it covers as much of the true surface as 1.2 (IoU 0.987 vs 0.985
// on the default view) and more than 1 (0.980). 64 steps of r reach a surface
// up to 64 r behind a splash in front of it (32 steps: IoU 0.975).

// The first parameter out of range, as "field: what is allowed"; empty when all are fine.
std::string checkRaycastParams(const RaycastParams& p);

// ---- Silhouette reduction (docs/pipeline.md#silhouette-reduction; Instant Liquids §3) ----

// Cords & Staadt's silhouette map: the binary fluid mask smoothed over a
// window around each fluid pixel gives the fraction S of fluid near it, below
// 1 only near a contour. Where S < 1 the liquid fades into what lies behind
// it, alpha = clamp((S - fadeFrom) / (1 - fadeFrom), 0, 1) (fadeFrom = 1: the
// paper's clip, liquid only where S = 1), which removes the ring of poorly
// smoothed depth and normals at the outer contour and softens the stair-step
// edge. Past the contour a background pixel next to the liquid takes the mean
// of its fluid neighbours' colours at the alpha of its own window's S (the
// window sized at their depth): with fadeFrom below 0.5 the fade continues
// past a straight contour, so edges end in a ramp rather than at the pixel
// grid; at 0.5 only notches in the liquid (S > 0.5 outside it) are filled.
// The window is a square of half-width radiusRadii r projected at the
// pixel's depth (at most maxPx), with uniform weights: exact integer counts
// from a summed-area table, O(1) a pixel on both backends. Off unless enabled.
struct SilhouetteParams {
    bool enabled = false;
    float radiusRadii = 1.0f;  // window half-width, particle radii
    int maxPx = 16;            // cap on the window half-width, pixels
    float fadeFrom = 0.5f;     // S at which the fade starts (0.5: a straight edge's own pixels); 1 = clip
};

// The first parameter out of range, as "field: what is allowed"; empty when all are fine.
std::string checkSilhouetteParams(const SilhouetteParams& p);

// ---- Whitewater (Ihmsen et al. 2012) -----------------------------------------

// Diffuse particles (spray, foam, air bubbles) generated from a fluid
// sequence: Ihmsen, Akinci, Akinci & Teschner, "Unified spray, foam and air
// bubbles for particle-based fluids", The Visual Computer 28 (CGI 2012).
// Defaults are SPlisHSPlasH's FoamGenerator's (Tools/FoamGenerator), the peer.
struct WhitewaterParams {
    float supportRadii = 4.0f;  // h of the potentials, classification and advection, particle radii (SPlisHSPlasH's 4 r)
    // Limits [min, max] of the three potentials (Ihmsen eq. 1's tau); a max of
    // 0 (the default) asks for the automatic limits: 0.1 and 1 times the mean
    // over the sequence of each frame's largest value (FoamGenerator's mode).
    float trappedAirMin = 0.0f, trappedAirMax = 0.0f;  // m/s (eq. 2: relative speed, kernel-weighted)
    float waveCrestMin = 0.0f, waveCrestMax = 0.0f;    // dimensionless (eq. 4-7: curvature along the motion)
    float energyMin = 0.0f, energyMax = 0.0f;          // J/kg (kinetic energy per unit mass, |v|^2 / 2)
    float trappedAirRate = 1.0f;  // k_ta (eq. 8), with `scale`
    float waveCrestRate = 1.0f;   // k_wc (eq. 8), with `scale`
    float scale = 1000.0f;        // diffuse particles per second at full potential (FoamGenerator's foamscale)
    int sprayBelow = 6;           // fewer fluid neighbours than this: spray (Ihmsen §6)
    int bubbleAbove = 20;         // more fluid neighbours than this: bubble; between: foam
    float buoyancy = 2.0f;        // k_b, bubbles' buoyancy in multiples of -gravity (eq. 12)
    float drag = 0.8f;            // k_d in [0, 1], bubbles' drag toward the fluid's velocity (eq. 12)
    float lifetimeMinS = 2.0f;    // foam lifetime, s: min + I_k X (max - min), X uniform in [0, 1)
    float lifetimeMaxS = 5.0f;
    glm::vec3 gravity{0.0f, -9.81f, 0.0f};  // m/s^2
    // Diffuse particles leaving this box (metres; the container, say) dissolve.
    // Empty (the default): the fluid's region so far grown by h, open upward.
    Bounds box;
    std::size_t maxParticles = 4'000'000;   // cap on the diffuse particles alive (bounded memory)
    std::uint64_t seed = 1;                 // the random numbers' seed (the same output for any thread count)
};

// RenderSettings::diffuse: foam drawn this many particle radii toward the eye.
namespace defaults {
inline constexpr float kDiffuseFoamLiftRadii = 2.0f;
}

// Checked by sim::checkWhitewaterParams (include/meniscus/whitewater.h).

// ---- Scene (docs/pipeline.md#scene) -----------------------------------------

struct SceneParams {
    bool background = true;                  // false: no floor/walls, transparent background
    // false: the floor only, its checker and fade centred under the box, the
    // sky behind (for a moving camera, around which walls would jump sides).
    bool walls = true;
    // The eye position that picks the walls' sides (the far side of the box
    // from it); none: each frame's own camera eye. A moving camera that keeps
    // the walls sets its first frame's eye here, so they stay put.
    std::optional<glm::vec3> wallsSeenFrom;
    // Box the studio is built around (floor under it, back walls behind it);
    // empty = the bounds of the particles being rendered. Set it once per
    // sequence so the studio does not move between frames.
    Bounds studioBounds;
    // The HDR environment map (docs/pipeline.md#environment-map; readEnvironmentMap
    // in meniscus/environment.h): where set, it replaces the procedural sky as
    // the background and in the reflections. Shared: frames keep one copy.
    std::shared_ptr<const EnvironmentImage> environment;
    float environmentRotationDeg = 0.0f;  // about the vertical axis, degrees
    float environmentIntensity = 1.0f;    // multiplies the map's radiance
    // A backdrop (include/meniscus/backdrop.h, docs/compositing.md): another
    // renderer's colour and depth of the set, seen by this camera (the same
    // size), in the studio's place; null: the studio. Shared: frames keep one
    // copy.
    std::shared_ptr<const BackdropImage> backdrop;
};

// ---- Shading (docs/pipeline.md#shading) -------------------------------------

// One material = the parameters of the shading equation.
struct Material {
    std::string name = defaults::kMaterialName;
    glm::vec3 fluidColor{0.03f, 0.19f, 0.27f};     // linear RGB seen through thick fluid
    glm::vec3 absorptionPerM{6.0f, 2.0f, 1.3f};    // Beer-Lambert k per channel, 1/m
    float ior = 1.33f;                              // Snell's law (refracted view ray); Schlick F0 = ((ior-1)/(ior+1))^2
    float refraction = 1.0f;                        // strength of the refracted ray's bend: 1 Snell's law, 0 straight through
    float specular = 0.6f;                          // k_s
    float shininess = 120.0f;                       // Blinn-Phong exponent
    float opacity = 0.0f;                           // 0 = transparent fluid, 1 = opaque (sand-like)
};

// Named presets: water (default), murky, milk, lava, sand. Returns false for an unknown name.
bool materialPreset(const std::string& name, Material* out);
// The preset names, comma separated (for --help).
std::string materialPresetNames();

struct ShadingParams {
    Material material;
    glm::vec3 lightDirWorld = glm::normalize(glm::vec3(-0.4f, 1.0f, 0.55f));  // toward the light
};

// ---- The stages' parameters, together ------------------------------------

// One member per screen-space stage that has parameters: RenderSettings
// carries them and each backend's frame receives them whole (one
// assignment), so a new stage's parameters are one member here and travel to
// its drivers with nothing written on the way.
struct StageParams {
    // The smoothing filter (docs/pipeline.md#smoothing).
    FilterParams filter = NarrowRangeParams{};
    ThicknessParams thickness;
    // Hole filling (docs/pipeline.md#hole-filling): on by default; the screen
    // path only (the ray cast and the mesh decide their own coverage).
    HoleFillParams holeFill;
    // The material, light and look of the shading (docs/pipeline.md#shading).
    ShadingParams shading;
    // Surface noise and foam (docs/pipeline.md#noise-and-foam); off unless
    // noise.enabled. The noise's pattern is seeded by the particles' `id`
    // attribute (their index when absent); with ids and velocities and a
    // frameIndex, particles whose velocity jumped since the previous frame get
    // rougher noise for a while.
    NoiseParams noise;
    // Velocity whitening (docs/pipeline.md#noise-and-foam, Instant Liquids §4):
    // off unless whitening.enabled; reads the particles' `velocity` attribute
    // (without it nothing is whitened).
    WhiteningParams whitening;
    // Spray (docs/pipeline.md#classification): off unless spray.enabled.
    // Particles below its density fraction (the `density` attribute, else
    // estimated from neighbours) are drawn as drops instead of surface.
    SprayParams spray;
    // Silhouette reduction (docs/pipeline.md#silhouette-reduction; Instant
    // Liquids §3): off unless silhouette.enabled; fades the liquid into the
    // scene near its contours.
    SilhouetteParams silhouette;
    // The SPH surface, ray cast (docs/pipeline.md#ray-cast-surface): off unless
    // raycast.enabled. Each covered pixel's ray is marched to the particles'
    // SPH iso-surface (the surface refsurf and the mesh path see), which takes
    // the place of the smoothing filter (`filter` is not used) and of the depth
    // normals; the splat draws spheres of raycast.coverRadii r (or the
    // ellipsoids, that much larger) only to start and bound the rays. Not with
    // `mesh`.
    RaycastParams raycast;
};

// ---- Isosurface extraction (docs/surface.md, include/meniscus/surface.h) ----

struct MeshParams {
    float radiusM = 0.0f;  // particle radius r, metres (> 0)
    SurfaceField field = defaults::kSurfaceField;
    float cubeSizeRadii = defaults::kCubeSizeRadii;  // cube edge in r
    float iso = defaults::kSurfaceIso;               // fraction of the rest value, in (0, 1.5]
    // Support (Rc or h) in r; 0 = the field's default above.
    float supportRadii = 0.0f;
    int blockCubes = defaults::kBlockCubes;  // n; blocks of n^3 cubes run in parallel
    int threads = 0;                         // 0 = all cores; the mesh is the same for any count
    // For validation: evaluate every cube of the grid (plain marching cubes over
    // the particles' bounding box) instead of following the surface from seeds.
    // Same mesh when the seeding finds every piece of surface; volume cost.
    bool exhaustive = false;
};

}  // namespace meniscus
