// Frame memory: the image buffers the CPU stages keep alive at the frame's
// peak (during shading and the read-back), per pixel.
#include "core/frame_memory.h"

#include <string>

#include <glm/glm.hpp>

namespace meniscus {

namespace {

// Bytes per pixel, buffer by buffer (src/cpu/backend.cpp's slots):
//   scene layer, cached: colour vec4 16 + depth float 4               20
//   raw depth 4, thickness 4, smoothed depth 4                         12
//   normals vec3                                                       12
//   shaded colour vec4                                                 16
//   a stage's scratch beside its output (filter ping-pong, thickness
//   blur and splat chord sums: float 4 + float 4)                       8
//   the output's conversion (applyView colour or 8-bit PNG rows)       16
constexpr std::uint64_t kBytesPerPixel = 20 + 12 + 12 + 16 + 8 + 16;
// Of those, the host copies of the raw depth, thickness and normal AOVs
// (4 + 4 + 12) are made only when every AOV is read back (an EXR), not for
// the colour alone (RenderSettings::colorOnly: a PNG). Measured on frame 21
// at 3840x2160: 64 bytes a pixel writing a PNG, 89 an EXR (whose writer adds
// its own rows; docs/performance.md, "Memory budget").
constexpr std::uint64_t kOtherAovBytesPerPixel = 20;
// With the surface noise: N float 4 and its foam AOV float 4; with the
// velocity whitening: its map float 4 (their sums are per-tile scratch).
constexpr std::uint64_t kNoiseBytesPerPixel = 8;
constexpr std::uint64_t kWhiteningBytesPerPixel = 4;
// Several fluids, per fluid (LayerImage): raw depth 4, depth 4, normal 12,
// thickness 4, colour 16, emission 16, transmittance 16, noise 4, whitening 4;
// and the fluid AOV 4.
constexpr std::uint64_t kLayerBytesPerPixel = 80;
constexpr std::uint64_t kFluidAovBytesPerPixel = 4;
// Tiles a particle's splat rectangle covers, on average (a bin entry each).
constexpr std::uint64_t kTilesPerParticle = 2;

}  // namespace

std::uint64_t frameBytes(int width, int height, bool noise, bool whitening, int fluids, bool colorOnly) {
    if (width <= 0 || height <= 0) return 0;
    const std::uint64_t perPixel =
        kBytesPerPixel - (colorOnly ? kOtherAovBytesPerPixel : 0) + (noise ? kNoiseBytesPerPixel : 0) +
        (whitening ? kWhiteningBytesPerPixel : 0) +
        (fluids > 1 ? std::uint64_t(fluids) * kLayerBytesPerPixel + kFluidAovBytesPerPixel : 0);
    return std::uint64_t(width) * std::uint64_t(height) * perPixel;
}

std::uint64_t renderBytesPerParticle(const ParticleView& v, bool anisotropy, bool raycast, bool noise) {
    // The caller's arrays, as the view sees them (a reader's ParticleSet).
    std::uint64_t b = sizeof(glm::vec3);
    if (v.velocity.present()) b += sizeof(glm::vec3);
    if (v.density.present()) b += sizeof(float);
    if (v.id.present()) b += sizeof(std::int64_t);
    if (v.fluid.present()) b += sizeof(std::int64_t);
    if (v.color.present()) b += sizeof(glm::vec3);
    if (v.radius.present()) b += sizeof(float);
    // The splat bins (src/cpu/splat.h): view-space centre 12, screen rectangle
    // 16 and its tile entries (4 each, kTilesPerParticle on average).
    b += 12 + 16 + 4 * kTilesPerParticle;
    // Anisotropy (src/core/anisotropy.cpp): smoothed centre 12 and shape 72
    // (EllipsoidShape, two mat3), and the bins' view-space ellipsoid 48
    // (ViewEllipsoid). Its neighbour grid (the points in cell order 12, the
    // order 4, the four-lane coordinates 12, a flag 1) is freed before the
    // splat, so the splat's peak is the larger.
    if (anisotropy) b += 12 + 72 + 48;
    // The ray cast (src/core/sph_field.h): its grid's copy of the points 12
    // and cell order 4, the four-lane coordinates 12, the shapes it starts on
    // 72 (when the anisotropy has not made them).
    if (raycast) b += 12 + 4 + 12 + (anisotropy ? 0 : 72);
    // The surface noise's id coordinate and whiteness, 4 each.
    if (noise) b += 8;
    return b;
}

Status checkRenderMemory(std::uint64_t particles, std::uint64_t bytesPerParticle, int width, int height,
                         std::uint64_t frame, const MemoryBudget& budget) {
    return checkMemory(particles * bytesPerParticle + frame,
                       "rendering " + std::to_string(particles) + " particles into a " + std::to_string(width) + "x" +
                           std::to_string(height) + " frame",
                       "select fewer particles (--select) or use a larger machine", kJobShare, budget);
}

Status checkFrameMemory(int width, int height, const MemoryBudget& budget, bool noise, bool whitening, int fluids,
                        bool colorOnly) {
    return checkMemory(frameBytes(width, height, noise, whitening, fluids, colorOnly),
                       "a " + std::to_string(width) + "x" + std::to_string(height) + " frame",
                       "choose a smaller --width/--height", kFrameShare, budget);
}

}  // namespace meniscus
