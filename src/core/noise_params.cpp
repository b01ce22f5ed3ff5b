// checkNoiseParams and checkWhiteningParams (include/meniscus/params.h): the
// ranges the surface-noise and whitening stages are written for
// (src/shared/surface_noise.h, velocity_map.h).
#include <cmath>
#include <string>

#include "meniscus/params.h"

namespace meniscus {

namespace {
bool within(float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; }
}  // namespace

std::string checkNoiseParams(const NoiseParams& p) {
    if (!within(p.spriteRadii, 0.25f, 16.0f)) return "spriteRadii: from 0.25 to 16 particle radii";
    if (!within(p.sigma, 0.05f, 4.0f)) return "sigma: from 0.05 to 4 sprite radii";
    if (!within(p.frequency, 0.0f, 64.0f)) return "frequency: from 0 to 64 cycles per sprite radius";
    if (p.octaves < 1 || p.octaves > 6) return "octaves: from 1 to 6";
    if (!within(p.lacunarity, 1.0f, 4.0f)) return "lacunarity: from 1 to 4";
    if (!within(p.gain, 0.0f, 1.0f)) return "gain: from 0 to 1";
    if (!within(p.depthFalloffRadii, 0.01f, 100.0f)) return "depthFalloffRadii: from 0.01 to 100 particle radii";
    if (!within(p.bump, 0.0f, 100.0f)) return "bump: from 0 to 100 sprite radii";
    if (!within(p.foamThreshold, 0.0f, 1000.0f)) return "foamThreshold: from 0 to 1000";
    if (!within(p.foamGain, 0.0f, 1e6f)) return "foamGain: from 0 to 1e6";
    for (int c = 0; c < 3; ++c)
        if (!within(p.foamColor[c], 0.0f, 1e3f)) return "foamColor: linear RGB, each from 0 to 1000";
    if (!within(p.turbulence.tauMps, 0.0f, 1e6f)) return "turbulence.tauMps: from 0 to 1e6 m/s";
    if (!within(p.turbulence.boost, 1.0f, 100.0f)) return "turbulence.boost: from 1 to 100";
    if (p.turbulence.holdFrames < 1 || p.turbulence.holdFrames > 100000)
        return "turbulence.holdFrames: from 1 to 100000";
    return {};
}

std::string checkWhiteningParams(const WhiteningParams& p) {
    if (!within(p.thresholdMps, 0.0f, 1e6f)) return "thresholdMps: from 0 to 1e6 m/s";
    if (!within(p.rampMps, 1e-6f, 1e6f)) return "rampMps: from 1e-6 to 1e6 m/s";
    if (!within(p.strength, 0.0f, 1.0f)) return "strength: from 0 to 1";
    for (int c = 0; c < 3; ++c)
        if (!within(p.color[c], 0.0f, 1e3f)) return "color: linear RGB, each from 0 to 1000";
    if (!within(p.spriteRadii, 0.25f, 16.0f)) return "spriteRadii: from 0.25 to 16 particle radii";
    if (!within(p.sigma, 0.05f, 4.0f)) return "sigma: from 0.05 to 4 sprite radii";
    if (!within(p.depthFalloffRadii, 0.01f, 100.0f)) return "depthFalloffRadii: from 0.01 to 100 particle radii";
    return {};
}

std::string checkSprayParams(const SprayParams& p) {
    if (!within(p.sprayDensity, 0.0f, 1.0f)) return "sprayDensity: from 0 to 1 (a fraction of the rest density)";
    if (!within(p.restDensityKgM3, 0.0f, 1e6f)) return "restDensityKgM3: from 0 (the frame's median) to 1e6 kg/m^3";
    if (!within(p.sizeRadii, 0.05f, 16.0f)) return "sizeRadii: from 0.05 to 16 particle radii";
    if (!within(p.streakSeconds, 0.0f, 10.0f)) return "streakSeconds: from 0 to 10 s";
    if (!within(p.opacity, 0.0f, 16.0f)) return "opacity: from 0 to 16";
    for (int c = 0; c < 3; ++c)
        if (!within(p.color[c], 0.0f, 1e3f)) return "color: linear RGB, each from 0 to 1000";
    return {};
}

std::string checkSilhouetteParams(const SilhouetteParams& p) {
    if (!within(p.radiusRadii, 0.01f, 64.0f)) return "radiusRadii: from 0.01 to 64 particle radii";
    if (p.maxPx < 1 || p.maxPx > 256) return "maxPx: from 1 to 256 pixels";
    if (!within(p.fadeFrom, 0.0f, 1.0f)) return "fadeFrom: from 0 to 1";
    return {};
}

std::string checkHoleFillParams(const HoleFillParams& p, const ThicknessParams& thickness) {
    if (!within(thickness.minRadii, 0.0f, 100.0f)) return "thickness.minRadii: from 0 to 100 particle radii";
    if (!p.enabled) return {};
    if (!within(p.maxSpanRadii, 0.0f, 64.0f)) return "holeFill.maxSpanRadii: from 0 to 64 particle radii";
    if (!within(p.jumpRadii, 0.0f, 1000.0f)) return "holeFill.jumpRadii: from 0 to 1000 particle radii";
    if (p.reachPx < 1 || p.reachPx > 254) return "holeFill.reachPx: from 1 to 254 pixels";
    if (p.passes < 0 || p.passes > 8) return "holeFill.passes: from 0 to 8";
    return {};
}

}  // namespace meniscus
