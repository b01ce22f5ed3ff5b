// The option tables and the policies made from them (include/meniscus/options.h).
#include "meniscus/options.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <mutex>
#include <sstream>
#include <type_traits>

#include "meniscus/geometry.h"
#include "meniscus/particles.h"
#include "meniscus/sim.h"
#include "meniscus/whitewater.h"

namespace meniscus {

namespace {

using R = RenderOptions;
using G = OptionGroup;

// Builders for the table rows (a row reads: name, group, unit, help, field).
template <class O = RenderOptions>
OptionSpec<O> row(std::string name, G group, std::string unit, std::string help,
                  std::type_identity_t<OptionRef (*)(O&)> field) {
    OptionSpec<O> s;
    s.name = std::move(name);
    s.group = group;
    s.unit = std::move(unit);
    s.help = std::move(help);
    s.field = field;
    return s;
}
template <class O>
OptionSpec<O> ranged(OptionSpec<O> s, double lo, double hi) {
    s.limits.min = lo, s.limits.max = hi;
    return s;
}
template <class O>
OptionSpec<O> oneOf(OptionSpec<O> s, std::vector<std::string> choices) {
    s.limits.choices = std::move(choices);
    return s;
}
RenderOptionSpec shown(RenderOptionSpec s, const char* panel, float lo = 0.0f, float hi = 0.0f, bool log = false) {
    s.widget.panel = panel;
    s.widget.lo = lo, s.widget.hi = hi, s.widget.log = log;
    return s;
}
template <class O>
OptionSpec<O> positive(OptionSpec<O> s) {
    s.limits.min = 0.0, s.limits.max = std::numeric_limits<double>::infinity(), s.limits.positive = true;
    return s;
}
template <class O>
OptionSpec<O> flagRow(OptionSpec<O> s) {
    s.flag = true;
    return s;
}
template <class O>
OptionSpec<O> noDefault(OptionSpec<O> s) {
    s.noDefault = true;
    return s;
}
// A list of `count` numbers.
template <class O>
OptionSpec<O> listOf(OptionSpec<O> s, std::size_t count) {
    s.limits.count = count;
    return s;
}

std::vector<std::string> splitNames(const std::string& list) {  // "a, b, c"
    std::vector<std::string> out;
    std::string item;
    std::istringstream in(list);
    while (std::getline(in, item, ',')) {
        item.erase(0, item.find_first_not_of(' '));
        item.erase(item.find_last_not_of(' ') + 1);
        if (!item.empty()) out.push_back(item);
    }
    return out;
}

std::vector<RenderOptionSpec> makeRenderTable() {
    const NoiseParams noise;
    const std::string sprite = std::to_string(int(noise.spriteRadii));
    constexpr double inf = std::numeric_limits<double>::infinity();
    std::vector<RenderOptionSpec> t;
    // Camera.
    t.push_back(ranged(row("width", G::Camera, "px", "Image width in pixels", [](R& o) -> OptionRef { return &o.width; }),
                       1, defaults::kMaxImageSizePx));
    t.push_back(ranged(row("height", G::Camera, "px", "Image height in pixels", [](R& o) -> OptionRef { return &o.height; }),
                       1, defaults::kMaxImageSizePx));
    t.push_back(row("eye", G::Camera, "m", "Camera position x,y,z in metres (default: automatic three-quarter view)",
                    [](R& o) -> OptionRef { return &o.eye; }));
    t.push_back(row("target", G::Camera, "m", "Point the camera looks at, x,y,z in metres",
                    [](R& o) -> OptionRef { return &o.target; }));
    t.push_back(row("up", G::Camera, "",
                    "The data's up axis x,y,z (0,0,1 for z-up data such as DualSPHysics'): the particles, --eye and "
                    "--target are turned so it points up in the picture, the studio's floor below",
                    [](R& o) -> OptionRef { return &o.up; }));
    t.push_back(positive(row("fov", G::Camera, "degrees", "Vertical field of view in degrees",
                             [](R& o) -> OptionRef { return &o.fov; })));
    t.back().limits.max = 179.0;  // as a camera path's fov between keys
    t.push_back(ranged(row("azimuth", G::Camera, "degrees",
                           "Automatic camera: the direction it looks from, degrees around the vertical (0: from +z, "
                           "90: from +x)",
                           [](R& o) -> OptionRef { return &o.azimuth; }),
                       -3600.0, 3600.0));
    t.push_back(ranged(row("elevation", G::Camera, "degrees", "Automatic camera: degrees above the horizon (-89 to 89)",
                           [](R& o) -> OptionRef { return &o.elevation; }),
                       -89.0, 89.0));
    t.push_back(noDefault(ranged(row("distance", G::Camera, "m",
                                     "Automatic camera: metres from the target (default: as close as frames the "
                                     "particles)",
                                     [](R& o) -> OptionRef { return &o.distance; }),
                                 0.0, inf)));
    // Input.
    t.push_back(noDefault(row("radius", G::Input, "m",
                              "Particle radius r in metres (default: the file's radius attribute, else estimated from "
                              "the bulk number density; docs/radius.md). Given, it also replaces a file's per-particle "
                              "radii (radius, pscale or particle_radius), which are otherwise drawn particle by particle",
                              [](R& o) -> OptionRef { return &o.radius; })));
    t.push_back(positive(row("h-per-spacing", G::Input, "spacings",
                           "A file with an SPH smoothing length (h, smoothing_length or hsml) and no radius: each "
                           "particle's radius is h / (2 K), K being h in particle spacings (PySPH's hdx, Chrono's "
                           "d0_multiplier; about 1.7 for DualSPHysics' coefh 1)",
                           [](R& o) -> OptionRef { return &o.hPerSpacing; })));
    // Output.
    t.push_back(oneOf(row("view", G::Output, "",
                          "What the image shows: final (shaded liquid), depth (smoothed eye depth), raw-depth (before "
                          "smoothing), normals, thickness, noise (surface noise N), foam (foam cover), whitening "
                          "(velocity whitening map), spray (the drops' cover), silhouette (the silhouette map)",
                          [](R& o) -> OptionRef { return &o.view; }),
                      splitNames(viewNames())));
    // Surface.
    t.push_back(oneOf(row("filter", G::Surface, "", "Depth smoothing: " + filterNames(),
                          [](R& o) -> OptionRef { return &o.filter; }),
                      splitNames(filterNames())));
    t.push_back(noDefault(ranged(row("iterations", G::Surface, "",
                                     "Smoothing iterations (default: the filter's own, e.g. 1 for narrow-range, 40 for "
                                     "curvature-flow)",
                                     [](R& o) -> OptionRef { return &o.iterations; }),
                                 0, 10000)));
    t.back().limits.unset = -1;  // the filter's own count
    t.push_back(flagRow(row("separable", G::Surface, "", "narrow-range: the faster separable 1-D approximation",
                            [](R& o) -> OptionRef { return &o.separable; })));
    // Look.
    t.push_back(row("material", G::Look, "",
                    "Fluid look: " + materialPresetNames() +
                        "; with several fluids one per fluid, comma-separated (e.g. water,lava: fluid 0 water, fluid 1 "
                        "lava)",
                    [](R& o) -> OptionRef { return &o.material; }));
    t.push_back(ranged(row("fluid-color", G::Look, "",
                           "Custom material, over the preset and for every fluid: the colour seen through thick "
                           "liquid, linear RGB r,g,b in [0, 1]",
                           [](R& o) -> OptionRef { return &o.fluidColor; }),
                       0.0, 1.0));
    t.push_back(ranged(row("absorption", G::Look, "1/m",
                           "Custom material: Beer-Lambert absorption per channel r,g,b, per metre (water: 6,2,1.3)",
                           [](R& o) -> OptionRef { return &o.absorption; }),
                       0.0, inf));
    t.push_back(ranged(row("ior", G::Look, "",
                           "Custom material: index of refraction (Snell's law and Fresnel F0; water 1.33)",
                           [](R& o) -> OptionRef { return &o.ior; }),
                       1.0, 4.0));
    t.push_back(ranged(row("refraction", G::Look, "",
                           "Custom material: strength of the refraction, the bend of the view ray entering the liquid "
                           "as a multiple of Snell's law's (1 physical, 0 the background straight behind; no unit)",
                           [](R& o) -> OptionRef { return &o.refraction; }),
                       0.0, 10.0));
    t.push_back(ranged(row("specular", G::Look, "", "Custom material: highlight strength k_s",
                           [](R& o) -> OptionRef { return &o.specular; }),
                       0.0, 10.0));
    t.push_back(ranged(row("shininess", G::Look, "", "Custom material: Blinn-Phong exponent",
                           [](R& o) -> OptionRef { return &o.shininess; }),
                       0.0, 100000.0));
    t.push_back(ranged(row("opacity", G::Look, "", "Custom material: 0 transparent liquid .. 1 opaque (sand)",
                           [](R& o) -> OptionRef { return &o.opacity; }),
                       0.0, 1.0));
    t.push_back(row("light", G::Look, "",
                    "Direction toward the key light x,y,z, world space (default -0.4,1,0.55: above, front left)",
                    [](R& o) -> OptionRef { return &o.light; }));
    t.push_back(row("geometry", G::Look, "",
                    "Scene geometry drawn around the liquid, repeatable: a mesh file (OBJ, PLY, STL, glTF, ...), a "
                    "SPlisHSPlasH scene file (its rigid bodies and boundaries; walls between the camera and the "
                    "liquid cut away), or geometry objects as JSON (a box, sphere, plane or file with a transform "
                    "and a material; docs/geometry.md). In the data's coordinates and units",
                    [](R& o) -> OptionRef { return &o.geometry; }));
    t.push_back(oneOf(row("cut-away", G::Look, "",
                          "on: the walls of containers (a SPlisHSPlasH scene's walls, a simulation's domain) between "
                          "the camera and the liquid are not drawn, the inside of the far walls shows; off: every "
                          "wall drawn",
                          [](R& o) -> OptionRef { return &o.cutAway; }),
                      {"on", "off"}));
    t.push_back(oneOf(row("shadows", G::Look, "",
                          "The key light's shadows of the scene geometry and of the liquid (coloured by its "
                          "absorption through the depth the light crosses) on the studio and the geometry: auto "
                          "(on when --geometry draws an object), on, off",
                          [](R& o) -> OptionRef { return &o.shadows; }),
                      {"auto", "on", "off"}));
    t.push_back(oneOf(row("boundary-particles", G::Look, "",
                          "DualSPHysics' boundary particles (Type 0 fixed, 1 moving, 2 floating) of a file with its "
                          "Type attribute: walls (taken out of the liquid and drawn as opaque surfaces meshed around "
                          "them at their own spacing; the fixed ones a container cut away as --cut-away says), liquid "
                          "(drawn as the liquid, as any particle), hidden (dropped). --select applies first",
                          [](R& o) -> OptionRef { return &o.boundaryParticles; }),
                      {"walls", "liquid", "hidden"}));
    // Extras.
    t.push_back(row("fluid-attribute", G::Extras, "",
                    "Several fluids: the integer particle attribute giving each particle's fluid, 0 to 3 (default: "
                    "the files' 'fluid' attribute, if any); each fluid is smoothed and shaded on its own, then "
                    "composited front to back",
                    [](R& o) -> OptionRef { return &o.fluidAttribute; }));
    t.push_back(oneOf(row("background", G::Look, "",
                          "studio (checker floor, two back walls, sky), floor (the checker floor alone, centred under "
                          "the particles, sky behind), none (transparent PNG background), or auto: studio for a still "
                          "camera, floor for one that moves (render --orbit, --turntable, --camera-path)",
                          [](R& o) -> OptionRef { return &o.background; }),
                      {"auto", "studio", "floor", "none"}));
    t.push_back(row("environment", G::Look, "",
                    "An HDR environment map, an equirectangular OpenEXR (.exr) or Radiance RGBE (.hdr) file "
                    "(linear RGB, at most 16384x8192): the background, what the liquid and the geometry reflect, and "
                    "the ambient light of the studio, the geometry, the liquid and the spray, instead of the "
                    "procedural sky (docs/pipeline.md#environment-map)",
                    [](R& o) -> OptionRef { return &o.environment; }));
    t.push_back(ranged(row("environment-rotation", G::Look, "degrees",
                           "The environment map's turn about the vertical axis, degrees",
                           [](R& o) -> OptionRef { return &o.environmentRotation; }),
                       -3600.0, 3600.0));
    t.push_back(ranged(row("environment-intensity", G::Look, "",
                           "A multiplier of the environment map's radiance",
                           [](R& o) -> OptionRef { return &o.environmentIntensity; }),
                       0.0, 1000.0));
    t.push_back(row("backdrop", G::Look, "",
                    "Another renderer's picture of the set to put the liquid into: an OpenEXR (.exr) with R, G, B "
                    "and its depth Z, or a PNG/JPEG with --backdrop-depth; made by this camera (--eye, --target, "
                    "--fov) at this size (--width, --height). It replaces the studio: the set hides the liquid where "
                    "it is nearer, and the liquid refracts and tints it (docs/compositing.md)",
                    [](R& o) -> OptionRef { return &o.backdrop; }));
    t.push_back(row("backdrop-depth", G::Look, "",
                    "The backdrop's depth as its own OpenEXR file: its Z channel, or its only channel",
                    [](R& o) -> OptionRef { return &o.backdropDepth; }));
    t.push_back(ranged(row("backdrop-first", G::Look, "frame number",
                           "With a backdrop sequence (a run of # in --backdrop or --backdrop-depth, as Blender names "
                           "an animation's frames: set_####.exr): the number of the file drawn behind the first "
                           "frame; frame i is drawn over file backdrop-first + i",
                           [](R& o) -> OptionRef { return &o.backdropFirst; }),
                       0.0, 999999999.0));
    t.push_back(row("backdrop-depth-kind", G::Look, "",
                    "What the backdrop's depth values are: linear (metres from the camera's plane), ray (metres "
                    "from the camera along the pixel's ray), blender (Blender 3+'s Z pass), window:NEAR,FAR "
                    "(OpenGL's 0-1 window depth of a projection with those planes, metres)",
                    [](R& o) -> OptionRef { return &o.backdropDepthKind; }));
    t.push_back(flagRow(row("noise", G::Extras, "",
                            "Surface noise and foam: small waves that travel with the particles, foam where they are "
                            "strong, rougher where velocities jump between frames (uses the files' id and velocity "
                            "attributes)",
                            [](R& o) -> OptionRef { return &o.stages.noise.enabled; })));
    t.push_back(row("noise-bump", G::Extras, "sprite radii",
                    "Height of the noise's waves, in sprite radii (a sprite is " + sprite +
                        " particle radii; 0 = no bumps, foam only)",
                    [](R& o) -> OptionRef { return &o.stages.noise.bump; }));
    t.push_back(row("noise-frequency", G::Extras, "1/sprite radius",
                    "Noise cycles per sprite radius (a sprite is " + sprite + " particle radii)",
                    [](R& o) -> OptionRef { return &o.stages.noise.frequency; }));
    t.push_back(row("noise-octaves", G::Extras, "", "Fractal octaves of the noise, 1 to 6",
                    [](R& o) -> OptionRef { return &o.stages.noise.octaves; }));
    t.push_back(row("foam", G::Extras, "", "Foam cover per unit of noise magnitude above the threshold (0 = no foam)",
                    [](R& o) -> OptionRef { return &o.stages.noise.foamGain; }));
    t.push_back(row("turbulence-tau", G::Extras, "m/s",
                    "Velocity change between frames, in m/s, above which a particle's noise is rougher for a while",
                    [](R& o) -> OptionRef { return &o.stages.noise.turbulence.tauMps; }));
    t.push_back(flagRow(row("whiten", G::Extras, "",
                            "Velocity whitening: fast water turns white (uses the files' velocity attribute)",
                            [](R& o) -> OptionRef { return &o.stages.whitening.enabled; })));
    t.push_back(row("whiten-threshold", G::Extras, "m/s", "Speed where whitening starts, in m/s",
                    [](R& o) -> OptionRef { return &o.stages.whitening.thresholdMps; }));
    t.push_back(row("whiten-ramp", G::Extras, "m/s", "Speed range over which whitening rises to full, in m/s",
                    [](R& o) -> OptionRef { return &o.stages.whitening.rampMps; }));
    t.push_back(row("whiten-strength", G::Extras, "", "White cover at full whitening, 0 to 1",
                    [](R& o) -> OptionRef { return &o.stages.whitening.strength; }));
    t.push_back(flagRow(row("spray", G::Extras, "",
                            "Spray: particles far below the rest density (the files' density attribute, else "
                            "estimated from their neighbours) are drawn as small drops streaked along their velocity, "
                            "not as surface",
                            [](R& o) -> OptionRef { return &o.stages.spray.enabled; })));
    t.push_back(row("spray-density", G::Extras, "", "Fraction of the rest density below which a particle is spray",
                    [](R& o) -> OptionRef { return &o.stages.spray.sprayDensity; }));
    t.push_back(row("rest-density", G::Extras, "kg/m^3",
                    "Rest density of the density attribute, kg/m^3 (0 = the frame's median density)",
                    [](R& o) -> OptionRef { return &o.stages.spray.restDensityKgM3; }));
    t.push_back(row("spray-size", G::Extras, "radii", "A drop's drawn radius, in particle radii",
                    [](R& o) -> OptionRef { return &o.stages.spray.sizeRadii; }));
    t.push_back(row("spray-streak", G::Extras, "s", "Exposure over which a drop is streaked along its path, in seconds",
                    [](R& o) -> OptionRef { return &o.stages.spray.streakSeconds; }));
    t.push_back(flagRow(row("silhouette", G::Extras, "",
                            "Silhouette reduction (Instant Liquids): near its contours, where less than all of a small "
                            "window around a pixel is liquid, the liquid fades into the scene behind it (softer, "
                            "anti-aliased edges, no rim of badly smoothed normals)",
                            [](R& o) -> OptionRef { return &o.stages.silhouette.enabled; })));
    t.push_back(row("silhouette-radius", G::Extras, "radii", "The window's half-width, in particle radii",
                    [](R& o) -> OptionRef { return &o.stages.silhouette.radiusRadii; }));
    t.push_back(row("silhouette-fade", G::Extras, "",
                    "Liquid fraction of the window at which the fade reaches 0 (0.5: a straight edge's own pixels; "
                    "below 0.5 the fade continues onto the background pixels just outside the liquid, in its colour; "
                    "1: clip, liquid only where the whole window is)",
                    [](R& o) -> OptionRef { return &o.stages.silhouette.fadeFrom; }));
    // Surface: anisotropy, hole filling, thin liquid.
    t.push_back(oneOf(row("anisotropy", G::Surface, "",
                          "Anisotropic kernels (Yu & Turk 2013), on or off: each particle is splatted as the ellipsoid "
                          "of its neighbours' spread (flat along a free surface, a sphere in the bulk, small when "
                          "alone), centred on its smoothed position; thin sheets close up and spray reads as droplets",
                          [](R& o) -> OptionRef { return &o.anisotropy; }),
                      {"on", "off"}));
    t.push_back(row("anisotropy-radius", G::Surface, "radii", "The neighbourhood's radius, in particle radii",
                    [](R& o) -> OptionRef { return &o.anisotropyParams.neighbourRadii; }));
    t.push_back(row("anisotropy-ratio", G::Surface, "", "Largest ratio of an ellipsoid's longest axis to its shortest",
                    [](R& o) -> OptionRef { return &o.anisotropyParams.kr; }));
    t.push_back(row("anisotropy-isolated", G::Surface, "radii",
                    "A particle with too few neighbours is a sphere of this many particle radii",
                    [](R& o) -> OptionRef { return &o.anisotropyParams.kn; }));
    t.push_back(row("anisotropy-neighbours", G::Surface, "",
                    "Fewer neighbours than this within the radius: the particle counts as isolated",
                    [](R& o) -> OptionRef { return &o.anisotropyParams.minNeighbours; }));
    t.push_back(row("anisotropy-keep-surface", G::Surface, "",
                    "Move each flattened free-surface ellipsoid outward so the surface stays where the spheres put it "
                    "(true or false)",
                    [](R& o) -> OptionRef { return &o.anisotropyParams.keepSurface; }));
    t.push_back(row("anisotropy-smoothing", G::Surface, "",
                    "How far each ellipsoid's centre moves toward its neighbours' weighted mean, 0 to 1",
                    [](R& o) -> OptionRef { return &o.anisotropyParams.smoothing; }));
    t.push_back(row("fill-holes", G::Surface, "radii",
                    "Fill the gaps the splat leaves inside a sheet of liquid, up to this many particle radii wide, "
                    "before the smoothing: where liquid of one surface closes a gap in along the row, the column and "
                    "both diagonals (a gap open to a side, between drops or between layers, stays); 0 = off",
                    [](R& o) -> OptionRef { return &o.fillHoles; }));
    t.push_back(row("min-thickness", G::Surface, "radii",
                    "Thin liquid: every liquid pixel is shaded as at least this many particle radii thick, so a sheet "
                    "one particle thick or the rim of a drop is tinted, never the untinted background; 0 = the "
                    "thickness as splatted",
                    [](R& o) -> OptionRef { return &o.stages.thickness.minRadii; }));
    t.push_back(row("fluid-scale", G::Performance, "",
                    "Reduced-resolution processing: 1, 0.5 or 0.25 of the width and height for the splat, smoothing, "
                    "normals and noise (about 4x or 16x fewer pixels); the surface is upsampled depth-aware and shaded "
                    "at full resolution",
                    [](R& o) -> OptionRef { return &o.fluidScale; }));
    t.push_back(oneOf(row("surface", G::Surface, "",
                          "screen: splat the particles as spheres and smooth the depth (the screen-space path); "
                          "raycast: splat them, then march each covered pixel's ray to the SPH iso-surface (the --field "
                          "sph surface at --iso with --support, exact normals, no smoothing; slower on the CPU); mesh: "
                          "extract the isosurface (as `meniscus mesh` does) and rasterise its triangles instead; the "
                          "thickness, scene and shading are the same",
                          [](R& o) -> OptionRef { return &o.surface; }),
                      {"screen", "raycast", "mesh"}));
    t.push_back(row("raycast-step", G::Surface, "radii", "--surface raycast: the march's step, in particle radii",
                    [](R& o) -> OptionRef { return &o.stages.raycast.stepRadii; }));
    t.push_back(row("raycast-steps", G::Surface, "",
                    "--surface raycast: steps a ray takes before it gives up (no surface at that pixel)",
                    [](R& o) -> OptionRef { return &o.stages.raycast.maxSteps; }));
    t.push_back(row("raycast-cover", G::Surface, "radii",
                    "--surface raycast: radius of the splatted spheres that start the rays, in particle radii (the "
                    "iso-surface reaches past the spheres of r between particles)",
                    [](R& o) -> OptionRef { return &o.stages.raycast.coverRadii; }));
    // The viewer's panels: header, slider range (log for wide ones).
    struct Widget {
        const char* name;
        const char* panel;
        float lo = 0.0f, hi = 0.0f;
        bool log = false;
    };
    const Widget widgets[] = {
        {"radius", "Surface", 0.25f, 4.0f, true},  // times the radius in use
        {"view", "Surface"},
        {"filter", "Surface"},
        {"iterations", "Surface", 0.0f, 100.0f},
        {"separable", "Surface"},
        {"fill-holes", "Surface", 0.0f, 16.0f},
        {"min-thickness", "Surface", 0.0f, 4.0f},
        {"fluid-scale", "Surface"},
        {"surface", "Surface"},
        {"raycast-step", "Surface", 0.05f, 2.0f},
        {"raycast-cover", "Surface", 1.0f, 4.0f},
        {"material", "Material"},
        {"fluid-color", "Material", 0.0f, 1.0f},
        {"absorption", "Material", 0.0f, 1000.0f},
        {"ior", "Material", 1.0f, 2.5f},
        {"refraction", "Material", 0.0f, 4.0f},
        {"specular", "Material", 0.0f, 4.0f},
        {"shininess", "Material", 1.0f, 4000.0f, true},
        {"opacity", "Material", 0.0f, 1.0f},
        {"anisotropy", "Anisotropy"},
        {"anisotropy-radius", "Anisotropy", 1.0f, 8.0f},
        {"anisotropy-ratio", "Anisotropy", 1.0f, 16.0f},
        {"anisotropy-isolated", "Anisotropy", 0.05f, 1.0f},
        {"anisotropy-neighbours", "Anisotropy", 1.0f, 50.0f},
        {"anisotropy-keep-surface", "Anisotropy"},
        {"anisotropy-smoothing", "Anisotropy", 0.0f, 1.0f},
        {"background", "Scene and light"},
        {"cut-away", "Scene and light"},
        {"shadows", "Scene and light"},
        {"boundary-particles", "Scene and light"},
        {"light", "Scene and light", -1.0f, 1.0f},
        {"noise", "Noise and foam"},
        {"noise-bump", "Noise and foam", 0.0f, 1.0f},
        {"noise-frequency", "Noise and foam", 0.05f, 4.0f, true},
        {"noise-octaves", "Noise and foam", 1.0f, 6.0f},
        {"foam", "Noise and foam", 0.0f, 8.0f},
        {"turbulence-tau", "Noise and foam", 0.01f, 10.0f, true},
        {"whiten", "Whitening"},
        {"whiten-threshold", "Whitening", 0.0f, 10.0f},
        {"whiten-ramp", "Whitening", 0.01f, 10.0f},
        {"whiten-strength", "Whitening", 0.0f, 1.0f},
        {"spray", "Spray"},
        {"spray-density", "Spray", 0.0f, 1.0f},
        {"rest-density", "Spray", 0.0f, 3000.0f},
        {"spray-size", "Spray", 0.05f, 2.0f},
        {"spray-streak", "Spray", 0.0f, 0.2f},
        {"silhouette", "Silhouette"},
        {"silhouette-radius", "Silhouette", 0.5f, 8.0f},
        {"silhouette-fade", "Silhouette", 0.0f, 1.0f},
    };
    for (const Widget& w : widgets)
        for (RenderOptionSpec& spec : t)
            if (spec.name == w.name) spec = shown(std::move(spec), w.panel, w.lo, w.hi, w.log);
    for (RenderOptionSpec& spec : t) {
        if (spec.name == "radius") spec.widget.relative = true;
        if (spec.name == "fluid-color") spec.widget.colour = true;
        if (spec.name.rfind("raycast-", 0) == 0) spec.widget.shownWith = "surface=raycast";
        if (spec.name == "surface") spec.widget.choices = {"screen", "raycast"};  // the viewer draws no mesh
        if (spec.name == "fluid-scale") spec.widget.choices = {"1", "0.5", "0.25"};
        if (spec.name == "material") spec.widget.choices = splitNames(materialPresetNames());
    }
    return t;
}

std::vector<MesherOptionSpec> makeMesherTable() {
    using M = MesherOptions;
    std::vector<MesherOptionSpec> t;
    // The ranges are the mesher's own (extractSurface), checked here so a bad
    // value is the option's error.
    t.push_back(ranged(row<M>("cube-size", G::Surface, "radii", "Marching-cubes cube edge, in particle radii (0.05 to 8)",
                              [](M& o) -> OptionRef { return &o.cubeSize; }),
                       0.05, 8.0));
    t.push_back(positive(row<M>("iso", G::Surface, "",
                                "Iso level as a fraction of the field inside fluid at rest (a 2r lattice); 0.5 puts a "
                                "flat face 1 r beyond the outermost particle centres",
                                [](M& o) -> OptionRef { return &o.iso; })));
    t.back().limits.max = 2.0;
    t.back().widget = {"Surface", 0.05f, 0.95f, false, false, false, {}, "surface=raycast"};  // the ray cast's level
    t.push_back(row<M>("field", G::Surface, "",
                     "sph: the SPH density, cubic spline of support 4 r (the surface refsurf ray-traces); thesis: "
                     "thesis eq. 4.16, f(d) = (d/(sqrt2 Rc))^4 - (d/(sqrt2 Rc))^2 + 1/4, Rc = 2.5 r",
                     [](M& o) -> OptionRef { return &o.field; }));
    t.back().limits.choices = {"sph", "thesis"};
    t.push_back(row<M>("support", G::Surface, "radii", "Field support (h or Rc) in particle radii, 1 to 16 (default: the field's)",
                     [](M& o) -> OptionRef { return &o.support; }));
    t.back().noDefault = true;
    t.back().limits.min = 1.0, t.back().limits.max = 16.0, t.back().limits.unset = 0.0;  // 0: the field's
    t.push_back(ranged(row<M>("block", G::Surface, "cubes", "Block edge in cubes (4 to 256); blocks run in parallel",
                              [](M& o) -> OptionRef { return &o.block; }),
                       4, 256));
    return t;
}

std::vector<JobOptionSpec> makeJobTable() {
    using J = JobOptions;
    std::vector<JobOptionSpec> t;
    t.push_back(row<J>("backend", G::Performance, "",
                     "Where the stages run: cpu, gl (OpenGL 4.3 through headless EGL) or auto (gl on a GPU; cpu, "
                     "with a one-line note, when there is no GL or only a software one such as Mesa's llvmpipe)",
                     [](J& o) -> OptionRef { return &o.backend; }));
    t.back().limits.choices = {"cpu", "gl", "auto"};
    t.push_back(row<J>("fluid", G::Extras, "",
                     "Several fluids, one input per fluid (as SPlisHSPlasH writes one file per fluid model): another "
                     "file or sequence, frame for frame with the input, drawn as fluid 1 (then 2, 3 when repeated); "
                     "the input is fluid 0. Give --material one preset per fluid",
                     [](J& o) -> OptionRef { return &o.moreFluids; }));
    t.back().path = true;
    t.push_back(row<J>("select", G::Input, "",
                     "Use only the particles that match, e.g. 'Type==fluid' (DualSPHysics: drops the boundary "
                     "particles) or 'density>900 && velocity.y<0': ATTR OP VALUE, OP one of == != < <= > >=, "
                     "clauses joined by && (all must hold). ATTR is a particle attribute as `meniscus info` lists it "
                     "(or x, y, z for the position), VALUE a number in the file's units (metres, m/s, kg/m^3); a "
                     "vector needs a component (velocity.x, .y, .z) or |velocity| for its length. DualSPHysics' Type "
                     "takes fixed (0), moving (1), floating (2), bound (0-2) or fluid (3). Applied to every file as "
                     "it is read, before --up; a frame left with no particles is an error",
                     [](J& o) -> OptionRef { return &o.select; }));
    t.push_back(row<J>("diffuse", G::Extras, "",
                     "Draw diffuse particles (spray, foam; `meniscus whitewater` writes them) over the liquid as drops "
                     "with the --spray-size and --spray-streak look: a file, or a pattern like diffuse_%04d.bgeo "
                     "filled with each input frame's number",
                     [](J& o) -> OptionRef { return &o.diffuse; }));
    t.back().path = true;
    t.push_back(row<J>("fps", G::Movie, "1/s",
                     "Frames per second: an .mp4 output's frame rate, and a moving camera's clock (frame i at i / fps "
                     "seconds)",
                     [](J& o) -> OptionRef { return &o.fps; }));
    t.back().limits.min = 0.001, t.back().limits.max = sim::kMaxFps;
    t.push_back(row<J>("crf", G::Movie, "",
                     "An .mp4 output's quality: x264's constant rate factor, 0 (lossless) to 51 (worst); 18 looks "
                     "lossless",
                     [](J& o) -> OptionRef { return &o.crf; }));
    t.back().limits.min = 0, t.back().limits.max = 51;
    t.push_back(row<J>("duration", G::Movie, "s",
                     "A simulation scene as the input: simulated time in seconds, a frame every 1/fps (default: the "
                     "scene's), as simulate --duration",
                     [](J& o) -> OptionRef { return &o.duration; }));
    t.back().limits.min = 0.0, t.back().limits.max = sim::kMaxDuration, t.back().limits.unset = -1.0;
    t.back().noDefault = true;
    t.push_back(row<J>("renumber", G::Output, "",
                     "Number the output images 0, 1, 2, ... in order instead of by the input files' own numbers",
                     [](J& o) -> OptionRef { return &o.renumber; }));
    t.back().flag = true;
    t.push_back(row<J>("on-error", G::Output, "",
                     "A frame that cannot be read, rendered or written: stop the run there (stop), or leave it out "
                     "and go on (skip), listing the failed frames at the end and exiting 1",
                     [](J& o) -> OptionRef { return &o.onError; }));
    t.back().limits.choices = {"stop", "skip"};
    t.push_back(row<J>("resume", G::Output, "",
                     "Leave frames whose output images already exist and are complete (after an interrupted run)",
                     [](J& o) -> OptionRef { return &o.resume; }));
    t.back().flag = true;
    t.push_back(row<J>("shard", G::Cluster, "",
                     "I/N: render only the I-th (from 0) of N contiguous shares of the frames, named as in the whole "
                     "run, for job arrays (Slurm: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT); the N runs "
                     "together write exactly the whole run's images",
                     [](J& o) -> OptionRef { return &o.shard; }));
    t.push_back(row<J>("split", G::Cluster, "",
                     "Under mpirun: give each process a share of the frames of a sequence (frames), or a share of "
                     "every frame's particles, splatted there and composited exactly on process 0 (particles; an "
                     "input with %r, e.g. fluid_r%r.vtu, gives each process its share of those part files); auto: "
                     "frames for a sequence, particles for one frame. The images are the one-process run's, byte for "
                     "byte",
                     [](J& o) -> OptionRef { return &o.split; }));
    t.back().limits.choices = {"auto", "frames", "particles"};
    t.push_back(row<J>("orbit", G::Movie, "degrees/s",
                     "Moving camera: turn about the vertical through the target at this many degrees per second of "
                     "sequence time (frame i at i / --fps seconds; positive: counter-clockwise seen from above), "
                     "keeping distance and elevation",
                     [](J& o) -> OptionRef { return &o.orbit; }));
    t.back().limits.min = -36000.0, t.back().limits.max = 36000.0, t.back().noDefault = true;
    t.push_back(row<J>("turntable", G::Movie, "",
                     "Moving camera: one whole turn about the vertical through the target over the sequence (frame i "
                     "of N at 360 i / N degrees); for a single file give --frames",
                     [](J& o) -> OptionRef { return &o.turntable; }));
    t.back().flag = true;
    t.push_back(row<J>("camera-path", G::Movie, "",
                     "Moving camera along key frames: a JSON file (or the JSON text itself) holding [{\"time\": s, "
                     "\"eye\": [x,y,z], \"target\": [x,y,z], \"fov\": degrees}, ...], times in seconds (frame i at "
                     "i / --fps), increasing; positions in metres, in the data's coordinates like --eye; fov optional "
                     "(default --fov); smooth (Catmull-Rom) between keys, the first and last key held before and after",
                     [](J& o) -> OptionRef { return &o.cameraPath; }));
    t.back().path = true;
    t.push_back(row<J>("frames", G::Movie, "",
                     "Render a single input file as N frames, numbered 0 to N-1 (a turntable of one frame: "
                     "--turntable --frames 120); without a moving camera the same picture N times",
                     [](J& o) -> OptionRef { return &o.frames; }));
    t.back().limits.min = 1, t.back().limits.max = 1000000, t.back().limits.unset = 0, t.back().noDefault = true;
    return t;
}

std::vector<MeshOptionSpec> makeMeshTable() {
    using M = MeshOptions;
    std::vector<MeshOptionSpec> t;
    t.push_back(noDefault(positive(row<M>("radius", G::Input, "m",
                                          "Particle radius r in metres (default: the median of the file's radius "
                                          "attribute or smoothing length, else estimated from the first frame)",
                                          [](M& o) -> OptionRef { return &o.radius; }))));
    t.back().limits.unset = 0.0;  // the file's, or estimated
    t.push_back(flagRow(row<M>("stats", G::Output, "",
                               "Print the extraction's phases, sizes and peak memory for each frame",
                               [](M& o) -> OptionRef { return &o.stats; })));
    t.push_back(flagRow(row<M>("resume", G::Output, "",
                               "Leave the outputs that already exist and are complete (after an interrupted run) "
                               "and write only the others, the same bytes as a whole run",
                               [](M& o) -> OptionRef { return &o.resume; })));
    t.push_back(row<M>("interpolate", G::Output, "",
                       "Particle attributes carried onto the vertices, NAME[,NAME...] (velocity, density, fluid or "
                       "any other the files have): each interpolated by the SPH kernel of the sph field's support, "
                       "normalised by the kernel sum; written into .ply (float properties), .vtp and .vtk (point "
                       "data), not .obj",
                       [](M& o) -> OptionRef { return &o.interpolate; }));
    t.push_back(ranged(row<M>("smoothing-iterations", G::Surface, "",
                              "Weighted Laplacian smoothing steps (Löschner et al. 2023, as splashsurf's "
                              "--mesh-smoothing-iters; 25 is splashsurf users' choice): the particle-scale bumps "
                              "flatten; 0: none",
                              [](M& o) -> OptionRef { return &o.smoothingIterations; }),
                       0.0, 10000.0));
    t.push_back(oneOf(row<M>("smoothing-weights", G::Surface, "",
                             "on: each vertex smoothed by a weight from its particles' neighbour counts, so "
                             "splashes and drops keep their shape and volume; off: every vertex fully (drops shrink)",
                             [](M& o) -> OptionRef { return &o.smoothingWeights; }),
                      {"on", "off"}));
    return t;
}

std::vector<SimulateOptionSpec> makeSimulateTable() {
    using S = SimulateOptions;
    std::vector<SimulateOptionSpec> t;
    t.push_back(noDefault(ranged(row<S>("duration", G::Simulation, "s",
                                        "Simulated time in seconds (default: the scene's)",
                                        [](S& o) -> OptionRef { return &o.duration; }),
                                 0.0, sim::kMaxDuration)));
    t.back().limits.unset = -1.0;  // the scene's
    t.push_back(noDefault(positive(row<S>("fps", G::Simulation, "1/s",
                                          "Frames written per simulated second (default: the scene's)",
                                          [](S& o) -> OptionRef { return &o.fps; }))));
    t.back().limits.max = sim::kMaxFps, t.back().limits.unset = -1.0;
    t.push_back(noDefault(positive(row<S>("radius", G::Simulation, "m",
                                          "Particle radius r in metres; spacing 2r, kernel support 4r (default: the "
                                          "scene's)",
                                          [](S& o) -> OptionRef { return &o.radius; }))));
    t.back().limits.unset = 0.0;
    t.push_back(noDefault(oneOf(row<S>("solver", G::Simulation, "",
                                       "dfsph (Bender & Koschier 2015), sph (Muller et al. 2003), pbf (position-based "
                                       "fluids, Macklin & Muller 2013) or ballistic (mass points, no pressure) "
                                       "(default: the scene's)",
                                       [](S& o) -> OptionRef { return &o.solver; }),
                                {"dfsph", "sph", "pbf", "ballistic"})));
    t.back().limits.emptyUnset = true;  // the scene's
    t.push_back(flagRow(row<S>("resume", G::Output, "",
                               "Continue from the last frame already written under the output pattern, to the same "
                               "bytes as a run never stopped (from the solver's checkpoint beside the frames, "
                               ".STEM.checkpoint; without a usable one, from the frame's particles and time)",
                               [](S& o) -> OptionRef { return &o.resume; })));
    t.push_back(flagRow(row<S>("stats", G::Output, "", "Print each frame's steps, solver iterations and time per phase",
                               [](S& o) -> OptionRef { return &o.stats; })));
    t.push_back(row<S>("render", G::Output, "",
                       "Also render each frame, as it is written, to this pattern with the same frame number: "
                       "out/img_%04d.png (8-bit sRGB) or .exr (float AOVs), or into one movie, out.mp4 (H.264 at the "
                       "simulation's frames per second). One camera for the whole sequence, framed on the scene's "
                       "domain (the tank); the particle radius is the simulation's",
                       [](S& o) -> OptionRef { return &o.render; }));
    t.back().path = true;
    return t;
}

std::vector<WhitewaterOptionSpec> makeWhitewaterTable() {
    using W = WhitewaterOptions;
    constexpr double inf = std::numeric_limits<double>::infinity();
    std::vector<WhitewaterOptionSpec> t;
    // Input.
    t.push_back(noDefault(positive(row<W>("radius", G::Input, "m",
                                          "Fluid particle radius r in metres (default: estimated from the first frame)",
                                          [](W& o) -> OptionRef { return &o.radius; }))));
    t.back().limits.unset = 0.0;
    t.push_back(noDefault(positive(row<W>("fps", G::Input, "1/s",
                                          "Frames per second of the input (default: estimated from how far the "
                                          "particles of the first two frames move along their velocities)",
                                          [](W& o) -> OptionRef { return &o.fps; }))));
    t.back().limits.unset = 0.0;
    // Generation.
    t.push_back(listOf(ranged(row<W>("limits", G::Generation, "",
                                     "Potential limits TA_MIN,TA_MAX,WC_MIN,WC_MAX,KE_MIN,KE_MAX: trapped air (m/s), "
                                     "wave crest (curvature, no unit), kinetic energy (J/kg). Default: automatic, 0.1 "
                                     "and 1 times the mean of each frame's largest value (one more pass over the input)",
                                     [](W& o) -> OptionRef { return &o.limits; }),
                              0.0, inf),
                       6));
    t.push_back(ranged(row<W>("scale", G::Generation, "1/s",
                              "Diffuse particles made per second by a particle at full potential",
                              [](W& o) -> OptionRef { return &o.scale; }),
                       0.0, 1e9));
    t.push_back(ranged(row<W>("trapped-air-rate", G::Generation, "",
                              "k_ta: weight of the trapped-air potential (a factor on --scale, no unit)",
                              [](W& o) -> OptionRef { return &o.trappedAirRate; }),
                       0.0, 1e9));
    t.push_back(ranged(row<W>("wave-crest-rate", G::Generation, "",
                              "k_wc: weight of the wave-crest potential (a factor on --scale, no unit)",
                              [](W& o) -> OptionRef { return &o.waveCrestRate; }),
                       0.0, 1e9));
    // Motion.
    t.push_back(listOf(ranged(row<W>("lifetime", G::Motion, "s", "Foam lifetime MIN,MAX in seconds",
                                     [](W& o) -> OptionRef { return &o.lifetime; }),
                              0.0, 1e6),
                       2));
    t.push_back(ranged(row<W>("buoyancy", G::Motion, "", "Bubbles' buoyancy k_b, in multiples of -gravity",
                              [](W& o) -> OptionRef { return &o.buoyancy; }),
                       0.0, 1e3));
    t.push_back(ranged(row<W>("drag", G::Motion, "", "Bubbles' drag k_d toward the fluid's velocity, 0 to 1",
                              [](W& o) -> OptionRef { return &o.drag; }),
                       0.0, 1.0));
    t.push_back(listOf(ranged(row<W>("gravity", G::Motion, "m/s^2", "Gravity X,Y,Z in m/s^2",
                                     [](W& o) -> OptionRef { return &o.gravity; }),
                              -1e4, 1e4),
                       3));
    t.push_back(listOf(row<W>("box", G::Motion, "m",
                              "MINX,MINY,MINZ,MAXX,MAXY,MAXZ in metres (the container): diffuse particles leaving it "
                              "dissolve. Default: the fluid's region so far, grown by 4 r, open upward",
                              [](W& o) -> OptionRef { return &o.box; }),
                       6));
    // Classes.
    t.push_back(ranged(row<W>("spray-below", G::Classes, "",
                              "Fewer fluid neighbours than this within 4 r (r: the particle radius): spray",
                              [](W& o) -> OptionRef { return &o.sprayBelow; }),
                       0, 100000));
    t.push_back(ranged(row<W>("bubble-above", G::Classes, "",
                              "More fluid neighbours than this: bubble (between: foam)",
                              [](W& o) -> OptionRef { return &o.bubbleAbove; }),
                       0, 100000));
    // Generation: the caps.
    t.push_back(ranged(row<W>("max-particles", G::Generation, "", "Most diffuse particles alive at once",
                              [](W& o) -> OptionRef { return &o.maxParticles; }),
                       1, 1e9));
    t.push_back(row<W>("seed", G::Generation, "", "Seed of the random numbers",
                       [](W& o) -> OptionRef { return &o.seed; }));
    t.push_back(flagRow(row<W>("resume", G::Output, "",
                               "Leave the output frames that already exist and are complete (after an interrupted "
                               "run) and write only the others, the same bytes as a whole run (the generator still "
                               "steps through every frame: its particles carry over from frame to frame)",
                               [](W& o) -> OptionRef { return &o.resume; })));
    return t;
}

std::string doubleText(double v) {  // the shortest text that reads back as the same double
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string numberText(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}


bool inRange(double v, double lo, double hi) {
    return !(v < lo) && !(v > hi) && !std::isnan(v);  // NaN bounds are open
}

std::string rangeText(double lo, double hi) {
    if (std::isnan(hi) || std::isinf(hi)) return lo == 0.0 ? "not negative" : "at least " + numberText(lo);
    return "in [" + numberText(lo) + ", " + numberText(hi) + "]";
}

}  // namespace

const char* optionGroupTitle(OptionGroup group) {
    switch (group) {
    case OptionGroup::Input: return "Input";
    case OptionGroup::Camera: return "Camera";
    case OptionGroup::Look: return "Look";
    case OptionGroup::Surface: return "Surface";
    case OptionGroup::Extras: return "Extras";
    case OptionGroup::Output: return "Output";
    case OptionGroup::Movie: return "Movie";
    case OptionGroup::Performance: return "Performance";
    case OptionGroup::Cluster: return "Cluster";
    case OptionGroup::Simulation: return "Simulation";
    case OptionGroup::Generation: return "Generation";
    case OptionGroup::Classes: return "Classes";
    case OptionGroup::Motion: return "Motion";
    case OptionGroup::Scripting: return "Scripting";
    }
    return "";
}

std::span<const RenderOptionSpec> renderOptionTable() {
    static const std::vector<RenderOptionSpec> table = makeRenderTable();
    return table;
}

std::span<const MesherOptionSpec> mesherOptionTable() {
    static const std::vector<MesherOptionSpec> table = makeMesherTable();
    return table;
}

std::span<const JobOptionSpec> jobOptionTable() {
    static const std::vector<JobOptionSpec> table = makeJobTable();
    return table;
}

std::span<const MeshOptionSpec> meshOptionTable() {
    static const std::vector<MeshOptionSpec> table = makeMeshTable();
    return table;
}

std::vector<ViewerOptionSpec> makeViewerTable() {
    using V = ViewerOptions;
    std::vector<ViewerOptionSpec> t;
    t.push_back(row<V>("simulate", G::Input, "",
                       "Instead of an input, simulate this scene file (.json, docs/scenes.md) live on a worker thread "
                       "and show its newest frame (a frame every 1/fps simulated seconds, played at most at real "
                       "time, to the scene's duration; simulated time and particle count in the title); the camera "
                       "is framed on the scene's domain. --radius then sets the simulation's particle radius in "
                       "metres (default: the scene's)",
                       [](V& o) -> OptionRef { return &o.simulate; }));
    t.back().path = true;
    t.push_back(row<V>("screenshot", G::Output, "",
                       "On exit, save the picture the window shows (without the panels) to this .png",
                       [](V& o) -> OptionRef { return &o.screenshot; }));
    t.back().path = true;
    t.push_back(row<V>("screenshot-window", G::Output, "", "On exit, save the whole window, panels included, to this .png",
                       [](V& o) -> OptionRef { return &o.screenshotWindow; }));
    t.back().path = true;
    t.push_back(noDefault(positive(row<V>("frames", G::Scripting, "", "Render and show N frames, then exit",
                                          [](V& o) -> OptionRef { return &o.frames; }))));
    t.back().limits.unset = 0.0;  // until the window is closed
    t.push_back(row<V>("input-script", G::Scripting, "",
                       "Replay input, one event per frame: drag:DX,DY;scroll:N;key:left|right|space|tab|h|c|q|"
                       "escape;drop:PATH;click:LABEL@F (a panel widget by its label, F the fraction of its width)",
                       [](V& o) -> OptionRef { return &o.inputScript; }));
    return t;
}

std::span<const ViewerOptionSpec> viewerOptionTable() {
    static const std::vector<ViewerOptionSpec> table = makeViewerTable();
    return table;
}

std::span<const SimulateOptionSpec> simulateOptionTable() {
    static const std::vector<SimulateOptionSpec> table = makeSimulateTable();
    return table;
}

std::span<const WhitewaterOptionSpec> whitewaterOptionTable() {
    static const std::vector<WhitewaterOptionSpec> table = makeWhitewaterTable();
    return table;
}

const JobOptionSpec* findJobOption(std::string_view name) { return findIn(jobOptionTable(), name); }

const RenderOptionSpec* findRenderOption(std::string_view name) { return findIn(renderOptionTable(), name); }
const MesherOptionSpec* findMesherOption(std::string_view name) { return findIn(mesherOptionTable(), name); }

// The shortest text that reads back as the same float (so a value printed by
// the viewer and given to `render` is the value the viewer drew with).
std::string floatText(float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string vec3Text(const glm::vec3& v) {
    return floatText(v.x) + "," + floatText(v.y) + "," + floatText(v.z);
}

std::string widgetLabel(const std::string& optionName, const std::string& unit) {
    std::string label = optionName;
    std::replace(label.begin(), label.end(), '-', ' ');
    return unit.empty() ? label : label + " (" + unit + ")";
}

std::string optionName(std::string_view keyword) {
    std::string s(keyword);
    std::replace(s.begin(), s.end(), '_', '-');
    return s;
}

std::string keywordName(std::string_view optionName) {
    std::string s(optionName);
    std::replace(s.begin(), s.end(), '-', '_');
    return s;
}

std::string optionText(const OptionRef& ref) {
    return std::visit(
        [&](auto* p) -> std::string {
            using T = std::remove_pointer_t<decltype(p)>;
            if constexpr (std::is_same_v<T, bool>) return *p ? "true" : "false";
            else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, std::uint64_t>) return std::to_string(*p);
            else if constexpr (std::is_same_v<T, float>) return std::isnan(*p) ? std::string() : floatText(*p);
            else if constexpr (std::is_same_v<T, std::vector<float>>) {
                std::string joined;
                for (float e : *p) joined += (joined.empty() ? "" : ",") + floatText(e);
                return joined;
            }
            else if constexpr (std::is_same_v<T, double>) return doubleText(*p);
            else if constexpr (std::is_same_v<T, std::string>) return *p;
            else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
                std::string joined;
                for (const std::string& e : *p) joined += (joined.empty() ? "" : ",") + e;
                return joined;
            }
            else if constexpr (std::is_same_v<T, glm::vec3>) return vec3Text(*p);
            else return *p ? vec3Text(**p) : std::string();
        },
        ref);
}

std::optional<glm::vec3> parseVec3(const std::string& text) {
    std::istringstream in(text);
    glm::vec3 v;
    char c1 = 0, c2 = 0;
    if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',') return std::nullopt;
    in >> std::ws;
    if (!in.eof() || !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return std::nullopt;
    return v;
}

Status checkOptionValue(const std::string& name, const OptionRef& ref, const OptionLimits& limits) {
    const std::string option = "--" + name;
    const double lo = limits.min, hi = limits.max;
    const std::vector<std::string>& choices = limits.choices;
    const auto bad = [&](const std::string& text, const std::string& why) {
        return makeUsageError("", option + " " + text + ": " + why);
    };
    return std::visit(
        [&](auto* p) -> Status {
            using T = std::remove_pointer_t<decltype(p)>;
            if constexpr (std::is_same_v<T, int> || std::is_same_v<T, float> || std::is_same_v<T, double> ||
                          std::is_same_v<T, std::uint64_t>) {
                if constexpr (std::is_floating_point_v<T>)
                    if (std::isnan(*p)) return okStatus();  // unset: the preset's
                if (double(*p) == limits.unset) return okStatus();
                if (limits.positive && !(*p > 0)) return bad(numberText(double(*p)), "expected a positive number");
                if ((!std::isnan(lo) || !std::isnan(hi)) && !inRange(double(*p), std::isnan(lo) ? -HUGE_VAL : lo,
                                                                     std::isnan(hi) ? HUGE_VAL : hi))
                    return bad(numberText(double(*p)), "expected a number " + rangeText(lo, hi));
            } else if constexpr (std::is_same_v<T, std::vector<float>>) {
                if (p->empty()) return okStatus();  // unset: the command's own
                if (limits.count && p->size() != limits.count)
                    return bad(optionText(p), "expected " + std::to_string(limits.count) + " numbers");
                for (float e : *p) {
                    if (!std::isfinite(e)) return bad(optionText(p), "expected finite numbers");
                    if (!std::isnan(lo) && !inRange(e, lo, std::isnan(hi) ? HUGE_VAL : hi))
                        return bad(optionText(p), "expected each number " + rangeText(lo, hi));
                }
            } else if constexpr (std::is_same_v<T, std::string>) {
                if (p->empty() && limits.emptyUnset) return okStatus();
                if (!choices.empty() && std::find(choices.begin(), choices.end(), *p) == choices.end()) {
                    if (choices.size() == 2) return bad(*p, "expected " + choices[0] + " or " + choices[1]);
                    std::string list;
                    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
                    return bad(*p, "expected one of " + list);
                }
            } else if constexpr (std::is_same_v<T, std::optional<glm::vec3>>) {
                if (*p && !(std::isfinite((**p).x) && std::isfinite((**p).y) && std::isfinite((**p).z)))
                    return bad(vec3Text(**p), "expected three finite numbers");
                if (*p && !std::isnan(lo))
                    for (int k = 0; k < 3; ++k)
                        if (!inRange((**p)[k], lo, std::isnan(hi) ? HUGE_VAL : hi))
                            return bad(vec3Text(**p), "each of x,y,z " + rangeText(lo, hi));
            }
            return okStatus();
        },
        ref);
}

Status setOptionValue(const std::string& name, const OptionRef& ref, const OptionValue& value,
                      const OptionLimits& limits) {
    const std::string option = "--" + name;
    const std::vector<std::string>& choices = limits.choices;
    const auto wrong = [&](const char* expected) { return makeUsageError("", option + ": expected " + std::string(expected)); };
    const bool isBool = std::holds_alternative<bool>(value);
    const bool isNumber = std::holds_alternative<std::int64_t>(value) || std::holds_alternative<double>(value);
    const double number = std::holds_alternative<std::int64_t>(value) ? double(std::get<std::int64_t>(value))
                          : std::holds_alternative<double>(value)     ? std::get<double>(value)
                                                                      : 0.0;
    // Set on a copy, checked, then stored: `o` keeps its value on an error.
    return std::visit(
        [&](auto* p) -> Status {
            using T = std::remove_pointer_t<decltype(p)>;
            T v = *p;
            if constexpr (std::is_same_v<T, bool>) {
                if (!isBool) return wrong("true or false");
                v = std::get<bool>(value);
            } else if constexpr (std::is_same_v<T, int>) {
                if (!std::holds_alternative<std::int64_t>(value) &&
                    !(std::holds_alternative<double>(value) && number == std::floor(number)))
                    return wrong("a whole number");
                if (!(std::fabs(number) < 2e9)) return wrong("a whole number in range");
                v = int(number);
            } else if constexpr (std::is_same_v<T, std::uint64_t>) {
                if (const auto* i = std::get_if<std::int64_t>(&value)) {
                    if (*i < 0) return wrong("a whole number, not negative");
                    v = std::uint64_t(*i);
                } else if (std::holds_alternative<double>(value) && number == std::floor(number) && number >= 0.0 &&
                           number < 1.8e19) {
                    v = std::uint64_t(number);
                } else return wrong("a whole number, not negative");
            } else if constexpr (std::is_same_v<T, std::vector<float>>) {
                // Numbers, three of them, or their text "a,b,c" (as the command line says them).
                v.clear();
                if (const auto* list = std::get_if<std::vector<double>>(&value)) v.assign(list->begin(), list->end());
                else if (const auto* three = std::get_if<glm::vec3>(&value)) v = {three->x, three->y, three->z};
                else if (const auto* text = std::get_if<std::string>(&value)) {
                    std::istringstream in(*text);
                    std::string item;
                    while (std::getline(in, item, ',')) {
                        char* end = nullptr;
                        const float e = std::strtof(item.c_str(), &end);
                        if (item.empty() || *end != '\0') return wrong("numbers separated by commas");
                        v.push_back(e);
                    }
                } else return wrong("a list of numbers");
                if (v.empty() && limits.count) return wrong((std::to_string(limits.count) + " numbers").c_str());
            } else if constexpr (std::is_same_v<T, float>) {
                if (!isNumber || !std::isfinite(number)) return wrong("a number");
                v = float(number);
            } else if constexpr (std::is_same_v<T, double>) {
                if (!isNumber || !std::isfinite(number)) return wrong("a number");
                v = number;
            } else if constexpr (std::is_same_v<T, std::string>) {
                // on/off options (anisotropy) take True/False too; a list is one text per fluid (material).
                if (isBool && choices.size() == 2 && choices[0] == "on") v = std::get<bool>(value) ? "on" : "off";
                else if (std::holds_alternative<std::string>(value)) v = std::get<std::string>(value);
                else if (const auto* list = std::get_if<std::vector<std::string>>(&value); list && !list->empty()) {
                    v.clear();
                    for (const std::string& e : *list) v += (v.empty() ? "" : ",") + e;
                } else return wrong("a text");
            } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
                if (const auto* list = std::get_if<std::vector<std::string>>(&value)) v = *list;
                else if (const auto* one = std::get_if<std::string>(&value)) v = {*one};
                else return wrong("a text or a list of texts");
            } else {
                // Three numbers, or their text "x,y,z" (as the command line and a hand-written file say them).
                std::optional<glm::vec3> read;
                if (std::holds_alternative<glm::vec3>(value)) read = std::get<glm::vec3>(value);
                else if (std::holds_alternative<std::string>(value)) read = parseVec3(std::get<std::string>(value));
                if (!read) return wrong("three numbers x,y,z");
                const glm::vec3 g = *read;
                if (!std::isfinite(g.x) || !std::isfinite(g.y) || !std::isfinite(g.z))
                    return wrong("three finite numbers x,y,z");
                v = g;
            }
            if (auto st = checkOptionValue(name, OptionRef(&v), limits); !st) return st;
            *p = std::move(v);
            return okStatus();
        },
        ref);
}

Status setJobOption(JobOptions& o, std::string_view name, const OptionValue& value) {
    if (const JobOptionSpec* s = findJobOption(name)) return setOption(*s, o, value);
    return makeUsageError("", "unknown option '" + std::string(name) + "'");
}

Status setRenderOption(RenderOptions& o, std::string_view name, const OptionValue& value) {
    if (const RenderOptionSpec* s = findRenderOption(name)) return setOption(*s, o, value);
    if (const MesherOptionSpec* s = findMesherOption(name)) return setOption(*s, o.mesher, value);
    std::string names;
    for (const RenderOptionSpec& s : renderOptionTable()) names += (names.empty() ? "" : ", ") + keywordName(s.name);
    for (const MesherOptionSpec& s : mesherOptionTable()) names += ", " + keywordName(s.name);
    return makeUsageError("", "unknown option '" + std::string(name) + "' (the options are: " + names + ")");
}

Status applySimulateOptions(const SimulateOptions& o, sim::Scene& scene) {
    if (auto st = checkOptions(simulateOptionTable(), o); !st) return st;
    if (o.duration >= 0.0) scene.duration = o.duration;
    if (o.fps > 0.0) scene.fps = o.fps;
    if (o.radius > 0.0f) scene.params.radius = o.radius;
    if (!o.solver.empty() && !sim::solverFromName(o.solver, &scene.params.solver))
        return makeUsageError("", "--solver " + o.solver + ": expected dfsph, sph, pbf or ballistic");
    return okStatus();
}

Result<WhitewaterParams> whitewaterParams(const WhitewaterOptions& o) {
    if (auto st = checkOptions(whitewaterOptionTable(), o); !st) return st.error();
    WhitewaterParams p;
    if (o.limits.size() == 6) {
        p.trappedAirMin = o.limits[0], p.trappedAirMax = o.limits[1];
        p.waveCrestMin = o.limits[2], p.waveCrestMax = o.limits[3];
        p.energyMin = o.limits[4], p.energyMax = o.limits[5];
        // A maximum of 0 would ask for the automatic limits.
        if (p.trappedAirMax == 0.0f || p.waveCrestMax == 0.0f || p.energyMax == 0.0f)
            return makeUsageError("", "--limits: every maximum must be above its minimum");
    }
    p.scale = o.scale;
    p.trappedAirRate = o.trappedAirRate;
    p.waveCrestRate = o.waveCrestRate;
    if (o.lifetime.size() == 2) p.lifetimeMinS = o.lifetime[0], p.lifetimeMaxS = o.lifetime[1];
    p.buoyancy = o.buoyancy;
    p.drag = o.drag;
    if (o.gravity.size() == 3) p.gravity = {o.gravity[0], o.gravity[1], o.gravity[2]};
    if (o.box.size() == 6) {
        if (!(o.box[0] < o.box[3] && o.box[1] < o.box[4] && o.box[2] < o.box[5]))
            return makeUsageError("", "--box: each minimum must be below its maximum");
        p.box.extend({o.box[0], o.box[1], o.box[2]});
        p.box.extend({o.box[3], o.box[4], o.box[5]});
    }
    p.sprayBelow = o.sprayBelow;
    p.bubbleAbove = o.bubbleAbove;
    p.maxParticles = std::size_t(o.maxParticles);
    p.seed = o.seed;
    if (std::string bad = sim::checkWhitewaterParams(p); !bad.empty()) return makeUsageError("", "whitewater: " + bad);
    return p;
}

namespace {

// One geometry spec's identity for the cache below: the text, and for a file
// its size and modification time (an edited file is read again).
std::string geometryKey(const std::string& spec) {
    std::string key = spec;
    std::error_code ec;
    const std::filesystem::path path(spec);
    if (!isInlineGeometry(spec) && std::filesystem::is_regular_file(path, ec)) {
        key += '\n' + std::to_string(std::filesystem::file_size(path, ec));
        key += '\n' + std::to_string(std::filesystem::last_write_time(path, ec).time_since_epoch().count());
    }
    return key;
}

}  // namespace

// The environment map of --environment, the last one read kept (the viewer
// and a sequence make settings again and again): read again when the path,
// the file's size or its modification time changes.
Result<std::shared_ptr<const EnvironmentImage>> renderEnvironment(const std::string& path) {
    static std::mutex mutex;
    static std::string lastKey;
    static std::shared_ptr<const EnvironmentImage> last;
    const std::string key = geometryKey(path);
    {
        std::lock_guard lock(mutex);
        if (last && key == lastKey) return last;
    }
    auto image = readEnvironmentMap(path);
    if (!image) return image.error();
    auto shared = std::make_shared<const EnvironmentImage>(std::move(*image));
    std::lock_guard lock(mutex);
    lastKey = key;
    last = shared;
    return shared;
}

Result<std::shared_ptr<const BackdropImage>> renderBackdrop(const std::string& color, const std::string& depth,
                                                            const std::string& depthKind) {
    auto kind = parseBackdropDepth(depthKind);
    if (!kind) return kind.error();
    static std::mutex mutex;
    static std::string lastKey;
    static std::shared_ptr<const BackdropImage> last;
    const std::string key = geometryKey(color) + '\n' + geometryKey(depth) + '\n' + depthKind;
    {
        std::lock_guard lock(mutex);
        if (last && key == lastKey) return last;
    }
    auto image = readBackdrop(color, depth, *kind);
    if (!image) return image.error();
    auto shared = std::make_shared<const BackdropImage>(std::move(*image));
    std::lock_guard lock(mutex);
    lastKey = key;
    last = shared;
    return shared;
}

bool backdropSequence(const RenderOptions& o) {
    return o.backdrop.find('#') != std::string::npos || o.backdropDepth.find('#') != std::string::npos;
}

std::string backdropFrameName(const std::string& pattern, std::int64_t number) {
    const std::size_t last = pattern.rfind('#');
    if (last == std::string::npos) return pattern;
    std::size_t first = last;
    while (first > 0 && pattern[first - 1] == '#') --first;
    std::string digits = std::to_string(number < 0 ? -number : number);
    const std::size_t width = last + 1 - first;
    if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
    if (number < 0) digits.insert(0, 1, '-');
    return pattern.substr(0, first) + digits + pattern.substr(last + 1);
}

Status backdropForFrame(const RenderOptions& o, std::size_t i, RenderSettings& s) {
    const std::int64_t number = std::int64_t(o.backdropFirst) + std::int64_t(i);
    const bool sequence = backdropSequence(o);
    const std::string color = backdropFrameName(o.backdrop, number);
    const std::string depth = backdropFrameName(o.backdropDepth, number);
    const std::string which = sequence ? "--backdrop (frame " + std::to_string(number) + " of the sequence): "
                                       : std::string("--backdrop: ");
    auto backdrop = renderBackdrop(color, depth, o.backdropDepthKind);
    if (!backdrop) return makeError(backdrop.error().file, which + backdrop.error().message);
    if (auto st = checkBackdropSize(**backdrop, o.width, o.height); !st)
        return makeUsageError(st.error().file, which + st.error().message);
    s.scene.backdrop = std::move(*backdrop);
    return okStatus();
}

Result<std::shared_ptr<const SceneGeometry>> renderGeometry(const std::vector<std::string>& specs,
                                                            const glm::vec3& upAxis, bool cutAway) {
    auto up = upRotation(upAxis);
    if (!up) return up.error();
    // The last list read, kept: the viewer makes settings again on every
    // change of an option, and a sequence once per frame range.
    static std::mutex mutex;
    static std::vector<std::string> lastKeys;
    static std::shared_ptr<const SceneGeometry> last;
    std::vector<std::string> keys;
    for (const std::string& spec : specs) keys.push_back(geometryKey(spec));
    keys.push_back(vec3Text(upAxis));
    keys.push_back(cutAway ? "cut away" : "whole");
    {
        std::lock_guard lock(mutex);
        if (last && keys == lastKeys) return last;
    }
    auto all = std::make_shared<SceneGeometry>();
    for (const std::string& spec : specs) {
        auto one = readGeometry(spec);
        if (!one) {
            return Error{one.error().file,
                         (isInlineGeometry(spec) ? "--geometry: " : "--geometry " + spec + ": ") + one.error().message,
                         one.error().usage};
        }
        all->append(std::move(*one));
    }
    if (!cutAway)
        for (GeometryObject& object : all->objects) object.cutaway = false;
    // Turned like the particles, so the objects stay where the data has them.
    if (!up->identity)
        for (GeometryObject& object : all->objects) {
            for (glm::vec3& p : object.mesh.positions) p = up->apply(p);
            for (glm::vec3& n : object.mesh.normals) n = up->apply(n);
        }
    std::lock_guard lock(mutex);
    lastKeys = std::move(keys);
    last = std::move(all);
    return last;
}

void frameGeometry(const SceneGeometry* geometry, std::vector<glm::vec3>& samplePoints, Bounds* studioBox) {
    if (!geometry) return;
    Bounds particles;
    for (const glm::vec3& p : samplePoints) particles.extend(p);
    const std::size_t weight = samplePoints.size() / 100 + 1;
    for (const GeometryObject& object : geometry->objects) {
        if (!object.visible || object.mesh.positions.empty()) continue;
        Bounds g;
        for (const glm::vec3& p : object.mesh.positions) g.extend(p);
        if (studioBox) {
            studioBox->extend(g.min);
            studioBox->extend(g.max);
        }
        if (object.cutaway && !particles.empty()) {
            g.min.y = std::max(g.min.y, particles.min.y);
            g.max.y = std::min(g.max.y, particles.max.y + 0.25f * particles.extent().y);
            if (!(g.min.y <= g.max.y)) continue;
        }
        for (int c = 0; c < 8; ++c)
            samplePoints.insert(samplePoints.end(), weight,
                                {c & 1 ? g.max.x : g.min.x, c & 2 ? g.max.y : g.min.y, c & 4 ? g.max.z : g.min.z});
    }
}

void addGeometry(RenderSettings& settings, SceneGeometry more, bool cutAway) {
    if (!cutAway)
        for (GeometryObject& object : more.objects) object.cutaway = false;
    auto all = std::make_shared<SceneGeometry>(settings.geometry ? *settings.geometry : SceneGeometry{});
    all->append(std::move(more));
    settings.geometry = std::move(all);
}

Status checkRenderOptions(const RenderOptions& o) {
    if (auto st = checkOptions(renderOptionTable(), o); !st) return st;
    return checkOptions(mesherOptionTable(), o.mesher);
}

Result<RenderSettings> renderSettings(const RenderOptions& o, bool diffuse) {
    if (auto st = checkRenderOptions(o); !st) return st.error();
    RenderSettings s;
    static_cast<StageParams&>(s) = o.stages;  // the stages' parameters whole; the filter and shading below
    if (!viewFromName(o.view, &s.view)) return makeUsageError("", "--view " + o.view + ": expected one of " + viewNames());
    if (!filterFromName(o.filter, &s.filter))
        return makeUsageError("", "--filter " + o.filter + ": expected one of " + filterNames());
    if (o.iterations >= 0) setFilterIterations(s.filter, o.iterations);
    if (o.separable) {
        auto* nr = std::get_if<NarrowRangeParams>(&s.filter);
        if (!nr) return makeUsageError("", "--separable applies to --filter narrow-range only");
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
        return makeUsageError("", "--material: " + std::to_string(names.size()) + " materials for at most " +
                                 std::to_string(kMaxFluids) + " fluids");
    for (const std::string& n : names) {
        Material m;
        if (!materialPreset(n, &m))
            return makeUsageError("", "--material " + n + ": expected one of " + materialPresetNames());
        if (o.fluidColor) m.fluidColor = *o.fluidColor;
        if (o.absorption) m.absorptionPerM = *o.absorption;
        if (!std::isnan(o.ior)) m.ior = o.ior;
        if (!std::isnan(o.refraction)) m.refraction = o.refraction;
        if (!std::isnan(o.specular)) m.specular = o.specular;
        if (!std::isnan(o.shininess)) m.shininess = o.shininess;
        if (!std::isnan(o.opacity)) m.opacity = o.opacity;
        s.fluidMaterials.push_back(m);
    }
    s.shading.material = s.fluidMaterials.front();
    if (o.light) {
        if (!(glm::length(*o.light) > 0.0f)) return makeUsageError("", "--light " + vec3Text(*o.light) + ": the direction toward the light cannot be zero (e.g. 1,2,1)");
        s.shading.lightDirWorld = *o.light;
    }
    s.scene.background = o.background != "none";
    s.scene.walls = o.background != "floor";  // auto: walls unless the caller sees the camera move
    if (!o.environment.empty()) {
        auto env = renderEnvironment(o.environment);
        if (!env) return makeError(env.error().file, "--environment: " + env.error().message);
        s.scene.environment = std::move(*env);
    }
    s.scene.environmentRotationDeg = o.environmentRotation;
    s.scene.environmentIntensity = o.environmentIntensity;
    if (auto kind = parseBackdropDepth(o.backdropDepthKind); !kind)
        return makeUsageError("", "--backdrop-depth-kind " + kind.error().message);
    if (!o.backdropDepth.empty() && o.backdrop.empty())
        return makeUsageError("", "--backdrop-depth " + o.backdropDepth + ": give the colour with --backdrop");
    if (!o.backdrop.empty())  // (a sequence: its first file, checked here; the others per frame)
        if (auto st = backdropForFrame(o, 0, s); !st) return st.error();
    const bool noise = o.stages.noise.enabled, whiten = o.stages.whitening.enabled;
    const bool spray = o.stages.spray.enabled, silhouette = o.stages.silhouette.enabled;
    if (noise)
        if (std::string bad = checkNoiseParams(s.noise); !bad.empty()) return makeUsageError("", "--noise: " + bad);
    if ((s.view == View::Noise || s.view == View::Foam) && !noise)
        return makeUsageError("", "--view " + o.view + " shows the surface noise: add --noise");
    if (whiten)
        if (std::string bad = checkWhiteningParams(s.whitening); !bad.empty()) return makeUsageError("", "--whiten: " + bad);
    if (s.view == View::Whitening && !whiten)
        return makeUsageError("", "--view whitening shows the velocity whitening: add --whiten");
    if (spray)
        if (std::string bad = checkSprayParams(s.spray); !bad.empty()) return makeUsageError("", "--spray: " + bad);
    if (s.view == View::Spray && !spray && !diffuse)
        return makeUsageError("", "--view spray shows the spray drops: add --spray (or --diffuse)");
    if (silhouette)
        if (std::string bad = checkSilhouetteParams(s.silhouette); !bad.empty()) return makeUsageError("", "--silhouette: " + bad);
    if (s.view == View::Silhouette && !silhouette)
        return makeUsageError("", "--view silhouette shows the silhouette map: add --silhouette");
    s.particleRadii = o.radius == 0.0f;  // an explicit radius replaces the file's own radii
    s.anisotropy = o.anisotropyParams;
    s.anisotropy.enabled = o.anisotropy == "on";
    if (s.anisotropy.enabled)
        if (std::string bad = checkAnisotropyParams(s.anisotropy); !bad.empty())
            return makeUsageError("", "--anisotropy: " + bad);
    s.holeFill.enabled = o.fillHoles > 0.0f;
    if (s.holeFill.enabled) s.holeFill.maxSpanRadii = o.fillHoles;
    if (std::string bad = checkHoleFillParams(s.holeFill, s.thickness); !bad.empty())
        return makeUsageError("", std::string(bad.rfind("thickness", 0) == 0 ? "--min-thickness: " : "--fill-holes: ") +
                                 bad);
    s.raycast.enabled = o.surface == "raycast";
    if (s.raycast.enabled) {
        if (o.mesher.field != "sph")
            return makeUsageError("", "--surface raycast: the ray cast finds the SPH surface: --field " + o.mesher.field +
                                     " is for --surface mesh");
        s.raycast.iso = o.mesher.iso;
        if (o.mesher.support > 0.0f) s.raycast.supportRadii = o.mesher.support;
        if (std::string bad = checkRaycastParams(s.raycast); !bad.empty())
            return makeUsageError("", "--surface raycast: " + bad);
    }
    if (o.fluidScale != 1.0f && o.fluidScale != 0.5f && o.fluidScale != 0.25f)
        return makeUsageError("", "--fluid-scale: expected 1, 0.5 or 0.25");
    if (o.fluidScale != 1.0f && o.surface == "mesh")
        return makeUsageError("", "--fluid-scale applies to the screen-space surface, not --surface mesh");
    s.fluidScale = o.fluidScale;
    s.shadows = o.shadows == "on" ? ShadowMode::On : o.shadows == "off" ? ShadowMode::Off : ShadowMode::Auto;
    if (!o.fluidAttribute.empty() && o.surface == "mesh")
        return makeUsageError("", "--fluid-attribute, --fluid: several fluids are drawn by the screen-space surface, not "
                             "--surface mesh");
    if (!(o.radius >= 0.0f)) return makeUsageError("", "--radius must be a positive number of metres");
    if (o.radius != 0.0f)
        if (auto st = checkRadius(o.radius); !st) return makeUsageError("", "--radius: " + st.error().message);
    if (!o.geometry.empty()) {
        auto geometry = renderGeometry(o.geometry, o.up, o.cutAway == "on");
        if (!geometry) return geometry.error();
        s.geometry = std::move(*geometry);
    }
    return s;
}

MeshParams mesherParams(const MesherOptions& o, float radiusM, int threads) {
    MeshParams p;
    p.radiusM = radiusM;
    surfaceFieldFromName(o.field, &p.field);
    p.cubeSizeRadii = o.cubeSize;
    p.iso = o.iso;
    p.supportRadii = o.support;
    p.blockCubes = o.block;
    p.threads = threads;
    return p;
}

glm::vec3 UpRotation::apply(const glm::vec3& v) const {
    if (identity) return v;
    // v c + (k x v) s + k (k . v)(1 - c)
    return v * c + glm::cross(axis, v) * s + axis * (glm::dot(axis, v) * (1.0f - c));
}

UpRotation UpRotation::inverse() const {
    UpRotation back = *this;
    back.s = -back.s;
    return back;
}

Result<UpRotation> upRotation(const glm::vec3& u) {
    if (!std::isfinite(u.x) || !std::isfinite(u.y) || !std::isfinite(u.z) || glm::length(u) == 0.0f)
        return makeUsageError("", "--up " + vec3Text(u) + ": expected the up axis as three numbers x,y,z, not all zero");
    const glm::vec3 n = glm::normalize(u), y(0.0f, 1.0f, 0.0f);
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

Result<float> resolveRadius(float optionRadius, const std::function<RadiusEstimate()>& estimate, std::string* note) {
    if (note) note->clear();
    if (optionRadius != 0.0f) {
        if (!(optionRadius > 0.0f)) return makeUsageError("", "--radius must be a positive number of metres");
        if (auto st = checkRadius(optionRadius); !st) return makeUsageError("", "--radius: " + st.error().message);
        return optionRadius;
    }
    const RadiusEstimate est = estimate();
    if (note) *note = std::string(est.fallback ? "warning: " : "") + "radius " + est.describe();
    if (auto st = checkRadius(est.radius); !st)
        return makeError("", "the estimated " + st.error().message + "; set --radius");
    return est.radius;
}

void sampleFramePoints(std::span<const glm::vec3> positions, std::vector<glm::vec3>& samples) {
    const std::size_t stride = std::max<std::size_t>(1, positions.size() / defaults::kSequenceFramePoints);
    for (std::size_t i = 0; i < positions.size(); i += stride) samples.push_back(positions[i]);
}

Result<Camera> chooseCamera(const RenderOptions& o, std::span<const glm::vec3> samplePoints, float radius,
                            std::size_t* outsideCount) {
    Camera cam;
    cam.width = o.width;
    cam.height = o.height;
    cam.fovYDegrees = o.fov;
    cam.nearM = defaults::kNearM;
    cam.farM = defaults::kFarM;
    if (o.eye.has_value() != o.target.has_value()) return makeUsageError("", "give both --eye and --target, or neither");
    if (o.eye) {
        auto up = upRotation(o.up);
        if (!up) return up.error();
        // In the data's coordinates, like the particles, which are turned to y up.
        cam.eye = up->apply(*o.eye);
        cam.target = up->apply(*o.target);
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
    }
    // The eye and target given (not framed on the data) are the caller's settings.
    if (auto st = validateCamera(cam); !st) return o.eye ? makeUsageError("", st.error().message) : st.error();
    return cam;
}

}  // namespace meniscus
