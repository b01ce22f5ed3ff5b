// The render options and sequence set-up shared by render, demo and view (see common.h).
#include "common.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>

#include "help_format.h"
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "scene_file.h"

namespace fs = std::filesystem;

namespace meniscus::app {

namespace {

// The camera (chooseCamera), radius and studio box for a whole sequence.
Status fixCamera(const RenderOptions& o, const std::vector<glm::vec3>& samplePoints, float radius,
                 const Bounds& studio, RenderSettings& settings) {
    auto camera = chooseCamera(o, samplePoints, radius);
    if (!camera) return camera.error();
    settings.camera = *camera;
    settings.radiusM = radius;
    settings.scene.studioBounds = studio;
    return okStatus();
}

}  // namespace

std::optional<glm::vec3> parseVec3(const std::string& text) {
    std::istringstream in(text);
    glm::vec3 v;
    char c1 = 0, c2 = 0;
    if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',') return std::nullopt;
    in >> std::ws;
    if (!in.eof() || !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return std::nullopt;
    return v;
}

Result<Camera> chooseCamera(const RenderOptions& o, std::span<const glm::vec3> samplePoints, float radius,
                            std::size_t* outsideCount) {
    Camera cam;
    cam.width = o.width;
    cam.height = o.height;
    cam.fovYDegrees = o.fov;
    cam.nearM = defaults::kNearM;
    cam.farM = defaults::kFarM;
    if (o.eye.empty() != o.target.empty()) return makeError("", "give both --eye and --target, or neither");
    if (!o.cameraPath.empty()) {
        // The path's first key; runRender moves the camera along the rest.
        if (!o.eye.empty()) return makeError("", "--camera-path sets the eye and target: leave out --eye and --target");
        auto keys = cameraPathFromOptions(o);
        if (!keys) return keys.error();
        cam.eye = keys->front().eye;
        cam.target = keys->front().target;
        cam.fovYDegrees = keys->front().fovYDegrees;
    } else if (!o.eye.empty()) {
        auto eye = parseVec3(o.eye), target = parseVec3(o.target);
        auto up = upRotation(o.up);
        if (!eye || !target) return makeError("", "--eye and --target take three numbers: x,y,z");
        if (!up) return up.error();
        // In the data's coordinates, like the particles, which are turned to y up.
        cam.eye = up->apply(*eye);
        cam.target = up->apply(*target);
        cam.up = {0.0f, 1.0f, 0.0f};
    } else {
        std::size_t outside = 0;
        cam = autoFrameCamera(samplePoints, radius, cam, &outside, o.azimuth, o.elevation);
        if (o.distance > 0.0f) {
            // Along the same direction; the clip range follows the new distance.
            const float fitted = glm::length(cam.eye - cam.target);
            cam.eye = cam.target + (cam.eye - cam.target) * (o.distance / fitted);
            cam.nearM = std::min(cam.nearM, 1e-3f * o.distance);
            cam.farM = std::max(cam.farM, cam.farM * o.distance / fitted);
            outside = 0;  // counted for the fitted distance
        }
        if (outsideCount) *outsideCount = outside;
        else if (outside > 0)
            std::cerr << "meniscus: auto camera: " << outside << " of " << samplePoints.size()
                      << " sampled particles (the outermost) left outside the frame\n";
    }
    if (auto st = validateCamera(cam); !st) return st.error();
    return cam;
}

void sampleFramePoints(std::span<const glm::vec3> positions, std::vector<glm::vec3>& samples) {
    const std::size_t stride = std::max<std::size_t>(1, positions.size() / defaults::kSequenceFramePoints);
    for (std::size_t i = 0; i < positions.size(); i += stride) samples.push_back(positions[i]);
}

int fail(const std::string& line) {
    std::cerr << "meniscus: error: " << line << "\n";
    return 1;
}

void printWarnings(const ParticleSet& set) {
    for (const auto& w : set.warnings) std::cerr << "meniscus: warning: " << w << "\n";
}

bool isExr(const std::string& path) { return fs::path(path).extension() == ".exr"; }
bool isPng(const std::string& path) { return fs::path(path).extension() == ".png"; }
bool isMp4(const std::string& path) { return fs::path(path).extension() == ".mp4"; }

void addSmoothingLengthOption(CLI::App* cmd, float& hPerSpacing) {
    cmd->add_option("--h-per-spacing", hPerSpacing,
                    "A file with an SPH smoothing length (h, smoothing_length or hsml) and no radius: each particle's "
                    "radius is h / (2 K), K being h in particle spacings (PySPH's hdx, Chrono's d0_multiplier; about "
                    "1.7 for DualSPHysics' coefh 1)")
        ->group(group::kInput)
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
}

void addCameraOptions(CLI::App* cmd, RenderOptions& o, bool radiusOption) {
    cmd->add_option("--width", o.width, "Image width in pixels")
        ->group(group::kCamera)
        ->capture_default_str()
        ->check(CLI::Range(1, defaults::kMaxImageSizePx));
    cmd->add_option("--height", o.height, "Image height in pixels")
        ->group(group::kCamera)
        ->capture_default_str()
        ->check(CLI::Range(1, defaults::kMaxImageSizePx));
    cmd->add_option("--eye", o.eye, "Camera position x,y,z in metres (default: automatic three-quarter view)")
        ->group(group::kCamera);
    cmd->add_option("--target", o.target, "Point the camera looks at, x,y,z in metres")
        ->group(group::kCamera);
    cmd->add_option("--up", o.up,
                    "The data's up axis x,y,z (0,0,1 for z-up data such as DualSPHysics'): the particles, --eye and "
                    "--target are turned so it points up in the picture, the studio's floor below")
        ->group(group::kCamera)
        ->capture_default_str();
    cmd->add_option("--fov", o.fov, "Vertical field of view in degrees")
        ->group(group::kCamera)
        ->capture_default_str();
    cmd->add_option("--azimuth", o.azimuth,
                    "Automatic camera: the direction it looks from, degrees around the vertical (0: from +z, 90: "
                    "from +x)")
        ->group(group::kCamera)
        ->capture_default_str()
        ->check(CLI::Range(-3600.0, 3600.0));
    cmd->add_option("--elevation", o.elevation, "Automatic camera: degrees above the horizon (-89 to 89)")
        ->group(group::kCamera)
        ->capture_default_str()
        ->check(CLI::Range(-89.0, 89.0));
    cmd->add_option("--distance", o.distance,
                    "Automatic camera: metres from the target (default: as close as frames the particles)")
        ->group(group::kCamera)
        ->check(CLI::NonNegativeNumber);
    if (radiusOption)
        cmd->add_option("--radius", o.radius,
                        "Particle radius r in metres (default: the file's radius attribute, else estimated from the "
                        "bulk number density; docs/radius.md). Given, it also replaces a file's per-particle radii "
                        "(radius, pscale or particle_radius), which are otherwise drawn particle by particle")
            ->group(group::kInput);
    if (radiusOption) addSmoothingLengthOption(cmd, o.hPerSpacing);
    cmd->add_option("--view", o.view,
                    "What the image shows: final (shaded liquid), depth (smoothed eye depth), raw-depth (before "
                    "smoothing), normals, thickness, noise (surface noise N), foam (foam cover), whitening (velocity "
                    "whitening map), spray (the drops' cover), silhouette (the silhouette map)")
        ->group(group::kOutput)
        ->capture_default_str();
    cmd->add_option("--filter", o.filter, "Depth smoothing: " + filterNames())
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--iterations", o.iterations,
                    "Smoothing iterations (default: the filter's own, e.g. 1 for narrow-range, 40 for curvature-flow)")
        ->group(group::kSurface)
        ->check(CLI::Range(0, 10000));
    cmd->add_flag("--separable", o.separable, "narrow-range: the faster separable 1-D approximation")
        ->group(group::kSurface);
    cmd->add_option("--material", o.material,
                    "Fluid look: " + materialPresetNames() +
                        "; with several fluids one per fluid, comma-separated (e.g. water,lava: fluid 0 water, fluid 1 lava)")
        ->group(group::kLook)
        ->capture_default_str();
    cmd->add_option("--fluid-color", o.fluidColor,
                    "Custom material, over the preset and for every fluid: the colour seen through thick liquid, "
                    "linear RGB r,g,b in [0, 1]")
        ->group(group::kLook);
    cmd->add_option("--absorption", o.absorption,
                    "Custom material: Beer-Lambert absorption per channel r,g,b, per metre (water: 6,2,1.3)")
        ->group(group::kLook);
    cmd->add_option("--ior", o.ior, "Custom material: index of refraction (Fresnel F0; water 1.33)")
        ->group(group::kLook)
        ->check(CLI::Range(1.0, 4.0));
    cmd->add_option("--refraction", o.refraction,
                    "Custom material: how far the background seen through the liquid is shifted, as a multiple of "
                    "the liquid's thickness projected onto the image (no unit)")
        ->group(group::kLook)
        ->check(CLI::Range(0.0, 10.0));
    cmd->add_option("--specular", o.specular, "Custom material: highlight strength k_s")
        ->group(group::kLook)
        ->check(CLI::Range(0.0, 10.0));
    cmd->add_option("--shininess", o.shininess, "Custom material: Blinn-Phong exponent")
        ->group(group::kLook)
        ->check(CLI::Range(0.0, 100000.0));
    cmd->add_option("--opacity", o.opacity, "Custom material: 0 transparent liquid .. 1 opaque (sand)")
        ->group(group::kLook)
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--light", o.light,
                    "Direction toward the key light x,y,z, world space (default -0.4,1,0.55: above, front left)")
        ->group(group::kLook);
    cmd->add_option("--fluid-attribute", o.fluidAttribute,
                    "Several fluids: the integer particle attribute giving each particle's fluid, 0 to 3 (default: "
                    "the files' 'fluid' attribute, if any); each fluid is smoothed and shaded on its own, then "
                    "composited front to back")
        ->group(group::kExtras);
    cmd->add_option("--background", o.background,
                    "studio (checker floor, two back walls, sky), floor (the checker floor alone, centred under the "
                    "particles, sky behind), none (transparent PNG background), or auto: studio for a still camera, "
                    "floor for one that moves (render --orbit, --turntable, --camera-path)")
        ->group(group::kLook)
        ->capture_default_str();
    NoiseParams& q = o.noiseParams;
    cmd->add_flag("--noise", o.noise,
                  "Surface noise and foam: small waves that travel with the particles, foam where they are strong, "
                  "rougher where velocities jump between frames (uses the files' id and velocity attributes)")
        ->group(group::kExtras);
    cmd->add_option("--noise-bump", q.bump,
                    "Height of the noise's waves, in sprite radii (a sprite is " + std::to_string(int(q.spriteRadii)) +
                        " particle radii; 0 = no bumps, foam only)")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--noise-frequency", q.frequency, "Noise cycles per sprite radius (a sprite is "
                    + std::to_string(int(q.spriteRadii)) + " particle radii)")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--noise-octaves", q.octaves, "Fractal octaves of the noise, 1 to 6")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--foam", q.foamGain, "Foam cover per unit of noise magnitude above the threshold (0 = no foam)")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--turbulence-tau", q.turbulence.tauMps,
                    "Velocity change between frames, in m/s, above which a particle's noise is rougher for a while")
        ->group(group::kExtras)
        ->capture_default_str();
    WhiteningParams& w = o.whitening;
    cmd->add_flag("--whiten", o.whiten,
                  "Velocity whitening: fast water turns white (uses the files' velocity attribute)")
        ->group(group::kExtras);
    cmd->add_option("--whiten-threshold", w.thresholdMps, "Speed where whitening starts, in m/s")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--whiten-ramp", w.rampMps, "Speed range over which whitening rises to full, in m/s")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--whiten-strength", w.strength, "White cover at full whitening, 0 to 1")
        ->group(group::kExtras)
        ->capture_default_str();
    SprayParams& sp = o.sprayParams;
    cmd->add_flag("--spray", o.spray,
                  "Spray: particles far below the rest density (the files' density attribute, else estimated from "
                  "their neighbours) are drawn as small drops streaked along their velocity, not as surface")
        ->group(group::kExtras);
    cmd->add_option("--spray-density", sp.sprayDensity, "Fraction of the rest density below which a particle is spray")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--rest-density", sp.restDensityKgM3,
                    "Rest density of the density attribute, kg/m^3 (0 = the frame's median density)")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--spray-size", sp.sizeRadii, "A drop's drawn radius, in particle radii")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--spray-streak", sp.streakSeconds,
                    "Exposure over which a drop is streaked along its path, in seconds")
        ->group(group::kExtras)
        ->capture_default_str();
    SilhouetteParams& sil = o.silhouetteParams;
    cmd->add_flag("--silhouette", o.silhouette,
                  "Silhouette reduction (Instant Liquids): near its contours, where less than all of a small window "
                  "around a pixel is liquid, the liquid fades into the scene behind it (softer, anti-aliased edges, no "
                  "rim of badly smoothed normals)")
        ->group(group::kExtras);
    cmd->add_option("--silhouette-radius", sil.radiusRadii, "The window's half-width, in particle radii")
        ->group(group::kExtras)
        ->capture_default_str();
    cmd->add_option("--silhouette-fade", sil.fadeFrom,
                    "Liquid fraction of the window at which the fade reaches 0 (0.5: a straight edge's own pixels; "
                    "below 0.5 the fade continues onto the background pixels just outside the liquid, in its "
                    "colour; 1: clip, liquid only where the whole window is)")
        ->group(group::kExtras)
        ->capture_default_str();
    AnisotropyParams& an = o.anisotropyParams;
    cmd->add_option("--anisotropy", o.anisotropy,
                    "Anisotropic kernels (Yu & Turk 2013), on or off: each particle is splatted as the ellipsoid of "
                    "its neighbours' spread (flat along a free surface, a sphere in the bulk, small when alone), "
                    "centred on its smoothed position; thin sheets close up and spray reads as droplets")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--anisotropy-radius", an.neighbourRadii, "The neighbourhood's radius, in particle radii")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--anisotropy-ratio", an.kr, "Largest ratio of an ellipsoid's longest axis to its shortest")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--anisotropy-isolated", an.kn,
                    "A particle with too few neighbours is a sphere of this many particle radii")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--anisotropy-neighbours", an.minNeighbours,
                    "Fewer neighbours than this within the radius: the particle counts as isolated")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--anisotropy-keep-surface", an.keepSurface,
                    "Move each flattened free-surface ellipsoid outward so the surface stays where the spheres put "
                    "it (true or false)")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--anisotropy-smoothing", an.smoothing,
                    "How far each ellipsoid's centre moves toward its neighbours' weighted mean, 0 to 1")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--fill-holes", o.fillHoles,
                    "Fill the gaps the splat leaves inside a sheet of liquid, up to this many particle radii wide, "
                    "before the smoothing: where liquid of one surface closes a gap in along the row, the column and "
                    "both diagonals (a gap open to a side, between drops or between layers, stays); 0 = off")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--min-thickness", o.minThickness,
                    "Thin liquid: every liquid pixel is shaded as at least this many particle radii thick, so a "
                    "sheet one particle thick or the rim of a drop is tinted, never the untinted background; 0 = the "
                    "thickness as splatted")
        ->group(group::kSurface)
        ->capture_default_str();
    cmd->add_option("--fluid-scale", o.fluidScale,
                    "Reduced-resolution processing: 1, 0.5 or 0.25 of the width and height for the splat, smoothing, "
                    "normals and noise (about 4x or 16x fewer pixels); the surface is upsampled depth-aware and shaded "
                    "at full resolution")
        ->group(group::kPerformance)
        ->capture_default_str();
}

void addBackendOption(CLI::App* cmd, RenderOptions& o) {
    cmd->add_option("--backend", o.backend,
                    "Where the stages run: cpu, gl (OpenGL 4.3 through headless EGL) or auto (gl on a GPU; cpu, "
                    "with a one-line note, when there is no GL or only a software one such as Mesa's llvmpipe)")
        ->group(group::kPerformance)
        ->capture_default_str();
}

Result<RenderSettings> settingsFromOptions(const RenderOptions& o) {
    RenderSettings s;
    if (!viewFromName(o.view, &s.view)) return makeError("", "--view " + o.view + ": expected one of " + viewNames());
    if (!filterFromName(o.filter, &s.filter))
        return makeError("", "--filter " + o.filter + ": expected one of " + filterNames());
    if (o.iterations >= 0) setFilterIterations(s.filter, o.iterations);
    if (o.separable) {
        auto* nr = std::get_if<NarrowRangeParams>(&s.filter);
        if (!nr) return makeError("", "--separable applies to --filter narrow-range only");
        nr->separable = true;
    }
    // One preset, or one per fluid (comma-separated: fluid 0's, fluid 1's, ...).
    std::vector<std::string> names;
    for (std::size_t at = 0;;) {
        const std::size_t comma = o.material.find(',', at);
        names.push_back(o.material.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    if (names.size() > std::size_t(kMaxFluids))
        return makeError("", "--material: " + std::to_string(names.size()) + " materials for at most " +
                                 std::to_string(kMaxFluids) + " fluids");
    for (const std::string& n : names) {
        Material m;
        if (!materialPreset(n, &m))
            return makeError("", "--material " + n + ": expected one of " + materialPresetNames());
        s.fluidMaterials.push_back(m);
    }
    auto vec3Option = [](const std::string& text, const char* name, glm::vec3* out) -> Status {
        if (text.empty()) return okStatus();
        auto v = parseVec3(text);
        if (!v)
            return makeError("", std::string(name) + " " + text + ": expected three numbers x,y,z");
        *out = *v;
        return okStatus();
    };
    for (Material& m : s.fluidMaterials) {
        if (auto st = vec3Option(o.fluidColor, "--fluid-color", &m.fluidColor); !st) return st.error();
        if (auto st = vec3Option(o.absorption, "--absorption", &m.absorptionPerM); !st) return st.error();
        if (!std::isnan(o.ior)) m.ior = o.ior;
        if (!std::isnan(o.refraction)) m.refraction = o.refraction;
        if (!std::isnan(o.specular)) m.specular = o.specular;
        if (!std::isnan(o.shininess)) m.shininess = o.shininess;
        if (!std::isnan(o.opacity)) m.opacity = o.opacity;
    }
    const Material& m0 = s.fluidMaterials.front();
    if (glm::any(glm::lessThan(m0.fluidColor, glm::vec3(0.0f))) || glm::any(glm::greaterThan(m0.fluidColor, glm::vec3(1.0f))))
        return makeError("", "--fluid-color " + o.fluidColor + ": each channel in [0, 1]");
    if (glm::any(glm::lessThan(m0.absorptionPerM, glm::vec3(0.0f))))
        return makeError("", "--absorption " + o.absorption + ": not negative");
    s.shading.material = s.fluidMaterials.front();
    if (auto st = vec3Option(o.light, "--light", &s.shading.lightDirWorld); !st) return st.error();
    if (!(glm::length(s.shading.lightDirWorld) > 0.0f)) return makeError("", "--light " + o.light + ": not zero");
    if (o.background != "auto" && o.background != "studio" && o.background != "floor" && o.background != "none")
        return makeError("", "--background " + o.background + ": expected auto, studio, floor or none");
    s.scene.background = o.background != "none";
    s.scene.walls = o.background != "floor";  // auto: walls unless runRender sees the camera move
    s.noise = o.noiseParams;
    s.noise.enabled = o.noise;
    if (o.noise)
        if (std::string bad = checkNoiseParams(s.noise); !bad.empty()) return makeError("", "--noise: " + bad);
    if ((s.view == View::Noise || s.view == View::Foam) && !o.noise)
        return makeError("", "--view " + o.view + " shows the surface noise: add --noise");
    s.whitening = o.whitening;
    s.whitening.enabled = o.whiten;
    if (o.whiten)
        if (std::string bad = checkWhiteningParams(s.whitening); !bad.empty()) return makeError("", "--whiten: " + bad);
    if (s.view == View::Whitening && !o.whiten)
        return makeError("", "--view whitening shows the velocity whitening: add --whiten");
    s.spray = o.sprayParams;
    s.spray.enabled = o.spray;
    if (o.spray)
        if (std::string bad = checkSprayParams(s.spray); !bad.empty()) return makeError("", "--spray: " + bad);
    if (s.view == View::Spray && !o.spray && o.diffuse.empty())
        return makeError("", "--view spray shows the spray drops: add --spray (or --diffuse)");
    s.silhouette = o.silhouetteParams;
    s.silhouette.enabled = o.silhouette;
    if (o.silhouette)
        if (std::string bad = checkSilhouetteParams(s.silhouette); !bad.empty()) return makeError("", "--silhouette: " + bad);
    if (s.view == View::Silhouette && !o.silhouette)
        return makeError("", "--view silhouette shows the silhouette map: add --silhouette");
    if (o.anisotropy != "on" && o.anisotropy != "off")
        return makeError("", "--anisotropy " + o.anisotropy + ": expected on or off");
    s.particleRadii = o.radius == 0.0f;  // an explicit --radius replaces the file's own radii
    s.anisotropy = o.anisotropyParams;
    s.anisotropy.enabled = o.anisotropy == "on";
    if (s.anisotropy.enabled)
        if (std::string bad = checkAnisotropyParams(s.anisotropy); !bad.empty())
            return makeError("", "--anisotropy: " + bad);
    s.holeFill.enabled = o.fillHoles > 0.0f;
    if (s.holeFill.enabled) s.holeFill.maxSpanRadii = o.fillHoles;
    s.thickness.minRadii = o.minThickness;
    if (std::string bad = checkHoleFillParams(s.holeFill, s.thickness); !bad.empty())
        return makeError("", std::string(bad.rfind("thickness", 0) == 0 ? "--min-thickness: " : "--fill-holes: ") +
                                 bad);
    s.raycast = o.raycastParams;
    s.raycast.enabled = o.surface == "raycast";
    if (s.raycast.enabled) {
        if (o.mesher.field != "sph")
            return makeError("", "--surface raycast: the ray cast finds the SPH surface: --field " + o.mesher.field +
                                     " is for --surface mesh");
        s.raycast.iso = o.mesher.iso;
        if (o.mesher.support > 0.0f) s.raycast.supportRadii = o.mesher.support;
        if (std::string bad = checkRaycastParams(s.raycast); !bad.empty())
            return makeError("", "--surface raycast: " + bad);
    }
    if (o.fluidScale != 1.0f && o.fluidScale != 0.5f && o.fluidScale != 0.25f)
        return makeError("", "--fluid-scale: expected 1, 0.5 or 0.25");
    if (o.fluidScale != 1.0f && o.surface == "mesh")
        return makeError("", "--fluid-scale applies to the screen-space surface, not --surface mesh");
    s.fluidScale = o.fluidScale;
    if ((!o.fluidAttribute.empty() || !o.moreFluids.empty()) && o.surface == "mesh")
        return makeError("", "--fluid-attribute, --fluid: several fluids are drawn by the screen-space surface, not "
                             "--surface mesh");
    if (!(o.radius >= 0.0f)) return makeError("", "--radius must be a positive number of metres");
    if (o.radius != 0.0f)
        if (auto st = checkRadius(o.radius); !st) return makeError("", "--radius: " + st.error().message);
    return s;
}

Result<Renderer> makeRenderer(const RenderOptions& o) {
    BackendChoice choice = BackendChoice::Auto;
    if (!backendFromName(o.backend, &choice))
        return makeError("", "--backend " + o.backend + ": expected one of " + backendNames());
    std::string note;
    auto made = Renderer::create(choice, &note);
    if (made && !note.empty()) std::cerr << "meniscus: " << note << "\n";
    return made;
}

Status writeImage(const std::string& path, const Aovs& aovs, bool withAlpha) {
    if (isExr(path)) return writeExrAovs(path, aovs);
    return writePng(path, aovs.color, withAlpha);
}

Status useFluidAttribute(ParticleSet& set, const std::string& name) {
    const Attribute* a = set.find(name);
    if (!a) {
        std::string have;
        for (const Attribute& b : set.attributes) have += (have.empty() ? "" : ", ") + b.name;
        return makeError("", "--fluid-attribute " + name + ": no such attribute (the file has: " +
                                 (have.empty() ? std::string("none") : have) + ")");
    }
    if (a->components != 1 || a->count() != set.size())
        return makeError("", "--fluid-attribute " + name + ": expected one value per particle, it has " +
                                 std::to_string(a->components) + " components");
    Attribute fluid;
    fluid.name = std::string(kAttrFluid);
    fluid.type = AttributeType::Int;
    if (a->type == AttributeType::Int) {
        fluid.ints = a->ints;
    } else {
        fluid.ints.reserve(a->floats.size());
        for (std::size_t i = 0; i < a->floats.size(); ++i) {
            const float v = a->floats[i];
            if (!(std::fabs(v) < 1e9f) || v != std::floor(v))
                return makeError("", "--fluid-attribute " + name + ": particle " + std::to_string(i) + " has " +
                                         std::to_string(v) + ", not a whole number");
            fluid.ints.push_back(std::int64_t(v));
        }
    }
    if (name == kAttrFluid) return okStatus();
    if (Attribute* old = set.find(kAttrFluid)) *old = std::move(fluid);
    else set.attributes.push_back(std::move(fluid));
    return okStatus();
}

void addFluidInputOption(CLI::App* cmd, RenderOptions& o) {
    cmd->add_option("--fluid", o.moreFluids,
                    "Several fluids, one input per fluid (as SPlisHSPlasH writes one file per fluid model): another "
                    "file or sequence, frame for frame with the input, drawn as fluid 1 (then 2, 3 when repeated); "
                    "the input is fluid 0. Give --material one preset per fluid")
        ->group(group::kExtras);
    addSelectOption(cmd, o.select);
}

void addSelectOption(CLI::App* cmd, std::string& select) {
    cmd->add_option("--select", select,
                    "Use only the particles that match, e.g. 'Type==fluid' (DualSPHysics: drops the boundary "
                    "particles) or 'density>900 && velocity.y<0': ATTR OP VALUE, OP one of == != < <= > >=, "
                    "clauses joined by && (all must hold). ATTR is a particle attribute as `meniscus info` lists it "
                    "(or x, y, z for the position), VALUE a number in the file's units (metres, m/s, kg/m^3); a "
                    "vector needs a component (velocity.x, .y, .z) or |velocity| for its length. DualSPHysics' Type "
                    "takes fixed (0), moving (1), floating (2), bound (0-2) or fluid (3). Applied to every file as "
                    "it is read, before --up; a frame left with no particles is an error")
        ->group(group::kInput);
}

Status Frames::setSelection(const std::string& text) {
    auto parsed = parseSelection(text);
    if (!parsed) return parsed.error();
    selection = std::move(*parsed);
    return okStatus();
}

void appendFluid(ParticleSet& set, const ParticleSet& more, int fluid) {
    constexpr std::int64_t kIdOffset = std::int64_t(1) << 40;
    if (!set.find(kAttrFluid)) {
        Attribute index;
        index.name = std::string(kAttrFluid);
        index.type = AttributeType::Int;
        index.ints.assign(set.size(), 0);
        set.attributes.push_back(std::move(index));
    }
    set.positions.insert(set.positions.end(), more.positions.begin(), more.positions.end());
    std::vector<Attribute> kept;
    for (Attribute& a : set.attributes) {
        if (a.name == kAttrFluid) {
            a.ints.resize(set.size(), std::int64_t(fluid));
            kept.push_back(std::move(a));
            continue;
        }
        const Attribute* b = more.find(a.name);
        if (!b || b->type != a.type || b->components != a.components || b->count() != more.size()) {
            set.warnings.push_back("attribute '" + a.name + "' is not in every fluid's file alike: left out");
            continue;
        }
        a.floats.insert(a.floats.end(), b->floats.begin(), b->floats.end());
        for (std::int64_t v : b->ints) a.ints.push_back(a.name == kAttrId ? v + std::int64_t(fluid) * kIdOffset : v);
        kept.push_back(std::move(a));
    }
    for (const Attribute& b : more.attributes)
        if (b.name != kAttrFluid &&
            std::none_of(set.attributes.begin(), set.attributes.end(), [&](const Attribute& a) { return a.name == b.name; }))
            set.warnings.push_back("attribute '" + b.name + "' is not in every fluid's file alike: left out");
    set.attributes = std::move(kept);
}

Status Frames::addFluids(const RenderOptions& o) {
    if (auto st = setSelection(o.select); !st) return st;
    fluidAttribute = o.fluidAttribute;
    if (o.moreFluids.empty()) return okStatus();
    if (!o.fluidAttribute.empty()) return makeError("", "--fluid and --fluid-attribute: give one or the other");
    if (embedded) return makeError("", "--fluid needs an input (the demo frame is one fluid)");
    if (o.moreFluids.size() + 1 > std::size_t(kMaxFluids))
        return makeError("", std::to_string(o.moreFluids.size() + 1) + " fluids (the input and " +
                                 std::to_string(o.moreFluids.size()) + " --fluid): at most " +
                                 std::to_string(kMaxFluids));
    for (const std::string& spec : o.moreFluids) {
        auto list = expandSequence(spec);
        if (!list) return list.error();
        if (list->size() != files.size())
            return makeError(spec, "--fluid: " + std::to_string(list->size()) + " frame(s), the input has " +
                                       std::to_string(files.size()));
        moreFluids.push_back(std::move(*list));
    }
    return okStatus();
}

glm::vec3 UpRotation::apply(const glm::vec3& v) const {
    if (identity) return v;
    // v c + (k x v) s + k (k . v)(1 - c)
    return v * c + glm::cross(axis, v) * s + axis * (glm::dot(axis, v) * (1.0f - c));
}

void UpRotation::apply(ParticleSet& set) const {
    if (identity) return;
    for (glm::vec3& p : set.positions) p = apply(p);
    Attribute* v = set.find(kAttrVelocity);
    if (v && v->type == AttributeType::Float && v->components == 3)
        for (std::size_t k = 0; k + 2 < v->floats.size(); k += 3) {
            const glm::vec3 t = apply(glm::vec3(v->floats[k], v->floats[k + 1], v->floats[k + 2]));
            v->floats[k] = t.x, v->floats[k + 1] = t.y, v->floats[k + 2] = t.z;
        }
}

Result<UpRotation> upRotation(const std::string& text) {
    const auto u = parseVec3(text);
    if (!u || glm::length(*u) == 0.0f)
        return makeError("", "--up " + text + ": expected the up axis as three numbers x,y,z, not all zero");
    const glm::vec3 n = glm::normalize(*u), y(0.0f, 1.0f, 0.0f);
    UpRotation r;
    const glm::vec3 a = glm::cross(n, y);
    const float s = glm::length(a);
    if (s == 0.0f) {
        if (n.y > 0.0f) return r;  // already up
        r.identity = false;        // upside down: half a turn about x
        r.axis = {1.0f, 0.0f, 0.0f};
        r.c = -1.0f;
        r.s = 0.0f;
        return r;
    }
    r.identity = false;
    r.axis = a / s;
    r.c = glm::dot(n, y);
    r.s = s;
    return r;
}

Result<ParticleSet> Frames::load(std::size_t i, std::string* smoothingLength) const {
    auto set = embedded ? Result<ParticleSet>(*embedded) : readParticles(files[source(i)]);
    // --select first: its positions and velocities are the file's, before --up.
    if (set)
        if (auto st = applySelection(*set, selection, name(i)); !st) return st.error();
    if (set) up.apply(*set);
    if (set) {
        auto h = addRadiusFromSmoothingLength(*set, hPerSpacing);
        if (!h) return h.error();
        if (smoothingLength) *smoothingLength = *h;
    }
    if (set && !fluidAttribute.empty())
        if (auto st = useFluidAttribute(*set, fluidAttribute); !st)
            return makeError(name(i), st.error().message);
    for (std::size_t k = 0; set && k < moreFluids.size(); ++k) {
        auto more = readParticles(moreFluids[k][source(i)]);
        if (!more) return more.error();
        if (auto st = applySelection(*more, selection, moreFluids[k][source(i)].string()); !st) return st.error();
        up.apply(*more);
        if (auto h = addRadiusFromSmoothingLength(*more, hPerSpacing); !h) return h.error();
        set->warnings.insert(set->warnings.end(), more->warnings.begin(), more->warnings.end());
        appendFluid(*set, *more, int(k) + 1);
    }
    return set;
}

Status Frames::checkOutput(const std::string& output, const char* example) const {
    if (count() > 1 && output.find('%') == std::string::npos)
        return makeError(output, std::to_string(count()) + " input frames need an output pattern with a frame number, e.g. " +
                                     example);
    return okStatus();
}

Result<std::string> Frames::outputName(const std::string& output, std::size_t i) const {
    if (output.find('%') == std::string::npos) return output;
    if (renumber || repeat) return formatFramePattern(output, long(i));
    const long number = embedded ? 0 : frameNumberOf(files[i]);  // run.h5part/Step#12 -> 12
    return formatFramePattern(output, number >= 0 ? number : long(i));
}

void printSmoothingLengthNote(const std::string& attribute, float hPerSpacing) {
    std::fprintf(stderr, "meniscus: radii from the smoothing length '%s': r = %s / (2 x %g) (--h-per-spacing)\n",
                 attribute.c_str(), attribute.c_str(), double(hPerSpacing));
}

Result<Frames> openFrames(const std::string& input, const ParticleSet* embedded, float hPerSpacing) {
    Frames frames;
    frames.embedded = embedded;
    frames.hPerSpacing = hPerSpacing;
    if (!embedded) {
        auto list = expandSequence(input);
        if (!list) return list.error();
        frames.files = std::move(*list);
    }
    return frames;
}

Result<ParticleSet> Frames::loadChecked(std::size_t i, std::string* smoothingLength) const {
    auto set = load(i, smoothingLength);
    if (!set) return set.error();
    if (auto st = checkCoordinates(set->positions, name(i)); !st) return st.error();
    return set;
}

std::string Frames::name(std::size_t i) const {
    if (!simulation.empty()) return simulation + " (frame " + std::to_string(i) + ")";
    return embedded ? std::string("the demo frame") : files[source(i)].string();
}

Result<ParticleSet> fixForSequence(const RenderOptions& o, const Frames& frames, RenderSettings& settings,
                                   std::size_t* firstIndex) {
    // With --on-error skip the first frame that loads sets the radius and the
    // studio, and the camera samples only frames that load.
    const bool skip = o.onError == "skip";
    std::string smoothingLength;
    std::size_t f = 0;
    auto first = frames.loadChecked(0, &smoothingLength);
    while (!first && skip && f + 1 < frames.count()) first = frames.loadChecked(++f, &smoothingLength);
    if (!first) return first.error();
    if (firstIndex) *firstIndex = f;
    const std::string firstName = frames.name(f);
    float radius = o.radius;
    if (radius == 0.0f) {
        const RadiusEstimate est = defaultRadius(*first);
        radius = est.radius;
        std::cerr << "meniscus: " << (est.fallback ? "warning: " : "") << "radius " << est.describe() << "\n";
        if (!smoothingLength.empty()) printSmoothingLengthNote(smoothingLength, frames.hPerSpacing);
        if (auto st = checkRadius(radius); !st)
            return makeError(firstName, "the estimated " + st.error().message + "; set --radius");
    }
    std::vector<glm::vec3> samplePoints;
    const auto addSample = [&](const std::vector<glm::vec3>& p) { sampleFramePoints(p, samplePoints); };
    const std::size_t count = frames.repeat ? 1 : frames.count();  // a repeated file: nothing more to sample
    if (o.eye.empty() && o.cameraPath.empty()) {
        addSample(first->positions);
        const std::size_t last = defaults::kSequenceFramingFrames - 1;
        for (std::size_t k = 1; count > 1 && k <= last; ++k) {
            const std::size_t i = k * (count - 1) / last;
            if (i <= f) continue;
            auto s = frames.loadChecked(i);
            if (!s && skip) continue;
            if (!s) return s.error();
            addSample(s->positions);
        }
    }
    // The studio is built around the first frame and stays put for the sequence.
    if (auto st = fixCamera(o, samplePoints, radius, computeBounds(first->positions), settings); !st)
        return st.error();
    return first;
}

Result<std::vector<CameraKey>> cameraPathFromOptions(const RenderOptions& o) {
    if (o.cameraPath.empty()) return std::vector<CameraKey>{};
    auto keys = readCameraPath(o.cameraPath, o.fov);
    if (!keys) return keys.error();
    auto up = upRotation(o.up);
    if (!up) return up.error();
    for (CameraKey& k : *keys) {
        k.eye = up->apply(k.eye);
        k.target = up->apply(k.target);
    }
    return keys;
}

Status fixForBox(const RenderOptions& o, const Bounds& box, float radiusM, RenderSettings& settings) {
    std::vector<glm::vec3> corners;
    for (int c = 0; c < 8; ++c)
        corners.push_back({c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                           c & 4 ? box.max.z : box.min.z});
    return fixCamera(o, corners, radiusM, box, settings);
}

}  // namespace meniscus::app
