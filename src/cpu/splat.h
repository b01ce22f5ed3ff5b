// CPU depth splat (docs/pipeline.md#depth-splat): exact ray-sphere nearest hit
// per pixel.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/anisotropy.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/sort_last.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// Pixel rectangle [x0, x1) × [y0, y1); empty when x0 >= x1 or y0 >= y1.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x0 >= x1 || y0 >= y1; }
};

// Exact screen-space bounding box of a sphere (view-space centre, radius) under
// perspective projection, clipped to the image; the whole image when the sphere
// reaches the eye plane. Empty when the sphere lies behind the camera.
PixelRect projectedSphereBounds(const Camera& camera, const glm::vec3& centreView, float radius);

// Eye depth of the nearest intersection of the pixel ray through (px, py) with
// the sphere, or +inf when the ray misses it (or the hit is behind the eye).
float raySphereEyeDepth(const glm::vec3& ray, const glm::vec3& centreView, float radius);

// depth(x, y) = min over particles of the nearest-hit eye depth, +inf where no
// sphere is hit. Hits nearer than camera.nearM or at/behind sceneDepth(x, y)
// (when given) are discarded. With `shapes` (one per position), each particle
// is its ellipsoid (anisotropic kernels, core/anisotropy.h) instead of the
// sphere of `radius`. Output does not depend on the thread count.
Image<float> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                        const Image<float>* sceneDepth = nullptr, std::span<const EllipsoidShape> shapes = {});

// ---- Shared by the depth and thickness splats --------------------------------
// (docs/pipeline.md#depth-splat, docs/pipeline.md#thickness)

// Particles binned into fixed kSplatTilePx-square screen tiles: view-space
// centres, exact projected rectangles, and per tile the indices of the spheres
// touching it (items[start[t] .. start[t+1]), in particle order, so the per-pixel
// processing order is fixed whatever the thread count).
inline constexpr int kSplatTilePx = 32;
// An ellipsoid in view space: shape m (shared/ellipsoid.h) and e = m c.
struct ViewEllipsoid {
    glm::mat3 m;
    glm::vec3 e;
};
struct SplatBins {
    int tilesX = 0, tilesY = 0;
    std::vector<glm::vec3> centres;  // view space
    std::vector<ViewEllipsoid> ellipsoids;  // one per centre, or empty: spheres of the radius
    std::vector<PixelRect> rects;
    std::vector<std::uint32_t> start;  // tilesX*tilesY + 1 offsets into items
    std::vector<std::uint32_t> items;
};
// With `shapes` (one per position): ellipsoids, splatted by the passes below
// with shared::rayEllipsoid instead of the sphere test.
SplatBins binParticles(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                       std::span<const EllipsoidShape> shapes = {});

// One pass over the bins, one task per tile. With `depth`: the nearest-hit eye
// depth as splatDepth. With `chords`: the summed length along the ray of each
// pixel ray inside the spheres, clipped to eye depths [camera.nearM,
// sceneDepth(x, y)), in fixed point: each chord rounded to whole units of
// radius / shared::kChordScale and added mod 2^32 (shared/splat_chords.h; the
// GL splat's arithmetic), so sums over any split of the particles add up to
// the same bits. Either output may be null; the non-null ones must be
// camera-sized and are fully overwritten.
void splatBins(const Camera& camera, const SplatBins& bins, float radius, const Image<float>* sceneDepth,
               Image<float>* depth, Image<std::uint32_t>* chords);

// The chord sums of splatBins on a coarser grid: one pixel per divisor x
// divisor block of the camera's pixels (divisor 1, 2 or 4; chords sized
// ceil(W / divisor) x ceil(H / divisor)), its ray through the block's centre,
// clipped at the nearest scene depth of the block. `bins` are the camera's
// full-resolution bins; spheres that cover no full-resolution pixel centre are
// not in them and so are left out here too.
void splatChordsLowRes(const Camera& camera, const SplatBins& bins, float radius, const Image<float>* sceneDepth,
                       int divisor, Image<std::uint32_t>& chords);

// The splat stage's first half (sort-last rendering, meniscus/sort_last.h):
// the depth as splatDepth and the fixed-point chord sums as splatBins, on the
// thickness grid of params.resolutionDivisor (the camera's pixels, or one per
// d x d block as splatChordsLowRes), in one pass over the particles. Nothing
// is resolved: the partials of any split of the particles combine (depth by
// min, chords by a wrapping sum) into the whole's partial, bit for bit, and
// resolveThickness (thickness.h) finishes the stage.
SplatPartial splatPartial(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                          const ThicknessParams& params, const Image<float>* sceneDepth = nullptr,
                          std::span<const EllipsoidShape> shapes = {});

}  // namespace meniscus::cpu
