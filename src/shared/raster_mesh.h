// The mesh path's image-size limit, written once for the CPU rasteriser and the
// Renderer that checks its preconditions. C++ only.
#pragma once

namespace meniscus::shared {

// Largest image side the CPU rasteriser's fixed-point edge functions hold
// exactly (int64, src/cpu/raster_mesh.cpp); also the width of its guard band.
inline constexpr int kRasterMaxSidePx = 1 << 16;

}  // namespace meniscus::shared
