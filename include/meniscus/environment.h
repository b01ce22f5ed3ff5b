// The HDR environment map (docs/pipeline.md#environment-map): an
// equirectangular linear RGB image that replaces the procedural sky as the
// background and in the reflections of the liquid and of the scene geometry.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "meniscus/result.h"

namespace meniscus {

// An environment map as read: width x height linear RGB texels, row after row
// from the top (the zenith), 3 floats each, finite and non-negative.
struct EnvironmentImage {
    int width = 0, height = 0;
    std::vector<float> rgb;
};

// The reader's bounds, checked before anything is allocated.
inline constexpr int kMaxEnvironmentWidth = 16384;
inline constexpr int kMaxEnvironmentHeight = 8192;
inline constexpr std::uintmax_t kMaxEnvironmentFileBytes = std::uintmax_t(1) << 30;  // 1 GiB

// Reads an equirectangular map: an OpenEXR file (.exr) with R, G and B
// channels (any pixel type, converted to float; a missing channel is an
// error), or a Radiance RGBE picture (.hdr or .pic: flat or run-length
// scanlines in the standard -Y H +X W orientation, EXPOSURE divided out; CIE
// XYZ pictures are refused). Non-finite and negative values become 0. Errors
// name the file; no exception escapes.
Result<EnvironmentImage> readEnvironmentMap(const std::filesystem::path& path);

}  // namespace meniscus
