// Frame memory: the image buffers the CPU stages keep alive at the frame's
// peak (during shading and the read-back), per pixel.
#include "core/frame_memory.h"

#include <cstdio>

#include <unistd.h>

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
// With the surface noise: N float 4 and its foam AOV float 4; with the
// velocity whitening: its map float 4 (their sums are per-tile scratch).
constexpr std::uint64_t kNoiseBytesPerPixel = 8;
constexpr std::uint64_t kWhiteningBytesPerPixel = 4;
// Several fluids, per fluid (LayerImage): raw depth 4, depth 4, normal 12,
// thickness 4, colour 16, emission 16, transmittance 16, noise 4, whitening 4;
// and the fluid AOV 4.
constexpr std::uint64_t kLayerBytesPerPixel = 80;
constexpr std::uint64_t kFluidAovBytesPerPixel = 4;

// The share of physical memory one frame may take.
constexpr double kMaxShare = 0.5;

}  // namespace

std::uint64_t frameBytes(int width, int height, bool noise, bool whitening, int fluids) {
    if (width <= 0 || height <= 0) return 0;
    const std::uint64_t perPixel =
        kBytesPerPixel + (noise ? kNoiseBytesPerPixel : 0) + (whitening ? kWhiteningBytesPerPixel : 0) +
        (fluids > 1 ? std::uint64_t(fluids) * kLayerBytesPerPixel + kFluidAovBytesPerPixel : 0);
    return std::uint64_t(width) * std::uint64_t(height) * perPixel;
}

std::uint64_t physicalMemoryBytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES);
    const long pageSize = ::sysconf(_SC_PAGESIZE);
    if (pages <= 0 || pageSize <= 0) return 0;
    return std::uint64_t(pages) * std::uint64_t(pageSize);
}

Status checkFrameMemory(int width, int height, std::uint64_t physicalBytes, bool noise, bool whitening, int fluids) {
    const std::uint64_t need = frameBytes(width, height, noise, whitening, fluids);
    if (physicalBytes == 0 || double(need) <= kMaxShare * double(physicalBytes)) return okStatus();
    char msg[256];
    std::snprintf(msg, sizeof msg,
                  "a %dx%d frame needs about %.1f GB of memory; this machine has %.1f GB, and a frame may use at "
                  "most half of it: choose a smaller --width/--height",
                  width, height, double(need) / 1e9, double(physicalBytes) / 1e9);
    return makeError("", msg);
}

}  // namespace meniscus
