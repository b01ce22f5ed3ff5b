// CPU depth splat, docs/pipeline.md#depth-splat. Each particle is a sphere of
// radius r; every pixel whose ray hits it gets the eye depth of the nearest
// intersection, and the minimum over particles wins. This is the exact,
// perspective-correct version of the point-sprite depth of van der Laan et al.
// 2009 (US 8,947,430) and Cords & Staadt 2008 ("Instant Liquids", §2.1; its eq.
// 2 gives the projected radius — here the exact projected bounding box is used
// instead).
//
// Parallel scheme: particles are binned into fixed screen tiles, then each tile
// is splatted by one task. A min is order-independent, so the result is the
// same for any thread count. The same bins and tile pass also sum the chord
// lengths of the thickness stage (docs/pipeline.md#thickness, thickness.cpp),
// alone or in the same pass as the depth, since both need the same ray-sphere
// intersection. The chords are summed in fixed point (shared/splat_chords.h,
// the GL splat's arithmetic): integer sums are exact and order-independent, so
// the partial sums of several processes (sort-last, meniscus/sort_last.h) add
// up to the whole's bits. The formulas (view-space centre, projected bounds,
// pixel rays, ray-sphere hit, its eye depth and clipped chord) are
// src/shared/splat.h, the GL twin's too.
#include "splat.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <tbb/parallel_for.h>

#include "cpu/filter_separable.h"  // detail::FloatV and its helpers
#include "shared/ellipsoid.h"
#include "shared/splat.h"
#include "shared/splat_chords.h"
#include "shared/thickness.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

namespace {
constexpr int kSplatTile = kSplatTilePx;
}  // namespace

namespace {

// The pixels whose centres lie within the image-plane slopes (xlo, xhi, ylo,
// yhi), clipped to the image (shared::splatRectFromSlopes).
PixelRect rectFromSlopes(const Camera& camera, float f, const glm::vec4& slopes) {
    const glm::ivec4 r = shared::splatRectFromSlopes(slopes, camera.width, camera.height, f);
    return {r.x, r.y, r.z, r.w};
}

// projectedSphereBounds with the focal length given (it costs a tan).
PixelRect sphereBounds(const Camera& camera, float f, const glm::vec3& c, float r) {
    glm::vec4 s;
    const int kind = shared::splatSphereSlopes(c, r, s);
    if (kind == 0) return {};                                   // wholly behind the eye
    if (kind == 1) return {0, 0, camera.width, camera.height};  // unbounded projection
    return rectFromSlopes(camera, f, s);
}

// The same for the ellipsoid of view-space centre c and outer form q (shared/ellipsoid.h).
PixelRect ellipsoidBounds(const Camera& camera, float f, const glm::vec3& c, const glm::mat3& q) {
    glm::vec4 s;
    const int kind = shared::ellipsoidSlopes(c, q, s);
    if (kind == 0) return {};
    if (kind == 1) return {0, 0, camera.width, camera.height};
    return rectFromSlopes(camera, f, s);
}

}  // namespace

PixelRect projectedSphereBounds(const Camera& camera, const glm::vec3& c, float r) {
    return sphereBounds(camera, camera.focalPx(), c, r);
}

float raySphereEyeDepth(const glm::vec3& ray, const glm::vec3& c, float r) {
    // Along the unit direction u = ray/|ray| (shared::raySphere). Since
    // ray.z = -1, the eye depth of the point t*u is t/|ray|.
    const float len = std::sqrt(glm::dot(ray, ray));
    const glm::vec3 u = ray / len;
    float b, h2;
    shared::raySphere(u.x, u.y, u.z, c, r * r, b, h2);
    if (h2 < 0.0f) return kInf;
    const float t = b - std::sqrt(h2);
    if (t <= 0.0f) return kInf;  // nearest hit behind the eye
    return t / len;
}

SplatBins binParticles(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                       std::span<const EllipsoidShape> shapes) {
    SplatBins bins;
    const int W = camera.width, H = camera.height;
    bins.tilesX = (W + kSplatTile - 1) / kSplatTile;
    bins.tilesY = (H + kSplatTile - 1) / kSplatTile;

    // View-space centres and screen rectangles, in parallel (independent per particle).
    const std::size_t n = positionsWorld.size();
    bins.centres.resize(n);
    bins.rects.resize(n);
    // (Camera::toView, with the view axes computed once instead of per particle.)
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back(), eye = camera.eye;
    const float f = camera.focalPx();
    const bool ellipsoids = !shapes.empty();
    if (ellipsoids) bins.ellipsoids.resize(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        const glm::vec3 c = shared::splatViewCentre(positionsWorld[i], eye, right, up, back);
        bins.centres[i] = c;
        if (!ellipsoids) {
            bins.rects[i] = sphereBounds(camera, f, c, radius);
            return;
        }
        // The shapes in view space (shared/ellipsoid.h, as gl/splat.comp).
        const glm::mat3 m = shared::ellipsoidToView(shapes[i].m, right, up, back);
        const glm::mat3 q = shared::ellipsoidToView(shapes[i].q, right, up, back);
        bins.ellipsoids[i] = {m, shared::ellipsoidMul(m, c)};
        bins.rects[i] = ellipsoidBounds(camera, f, c, q);
    });

    // Bin particle indices per tile, in particle order: kSlices fixed slices of
    // the particles count their tiles in parallel, a prefix sum over (tile,
    // slice) gives each slice its own range of every bin, and the slices fill
    // them in parallel. The bins do not depend on the thread count.
    constexpr std::size_t kSlices = 16;
    const int tilesX = bins.tilesX;
    const std::size_t tiles = std::size_t(bins.tilesX) * std::size_t(bins.tilesY);
    auto forTiles = [&](const PixelRect& r, auto&& fn) {
        if (r.empty()) return;
        for (int ty = r.y0 / kSplatTile; ty <= (r.y1 - 1) / kSplatTile; ++ty)
            for (int tx = r.x0 / kSplatTile; tx <= (r.x1 - 1) / kSplatTile; ++tx) fn(std::size_t(ty) * tilesX + tx);
    };
    std::vector<std::uint32_t> next(kSlices * tiles, 0);  // [slice][tile]: count, then fill position
    auto perSlice = [&](auto&& fn) {
        tbb::parallel_for(std::size_t(0), kSlices, [&](std::size_t c) {
            std::uint32_t* slice = &next[c * tiles];
            for (std::size_t i = n * c / kSlices; i < n * (c + 1) / kSlices; ++i) fn(slice, i);
        });
    };
    perSlice([&](std::uint32_t* slice, std::size_t i) { forTiles(bins.rects[i], [&](std::size_t t) { ++slice[t]; }); });
    auto& start = bins.start;
    start.assign(tiles + 1, 0);
    std::uint32_t total = 0;
    for (std::size_t t = 0; t < tiles; ++t) {
        start[t] = total;
        for (std::size_t c = 0; c < kSlices; ++c) {
            const std::uint32_t count = next[c * tiles + t];
            next[c * tiles + t] = total;
            total += count;
        }
    }
    start[tiles] = total;
    bins.items.resize(total);
    perSlice([&](std::uint32_t* slice, std::size_t i) {
        forTiles(bins.rects[i], [&](std::size_t t) { bins.items[slice[t]++] = std::uint32_t(i); });
    });
    return bins;
}

namespace {

using detail::FloatV;
using detail::IntV;
using detail::kLanes;
static_assert(kLanes == 4, "the tile loops below are written for 4 lanes");

inline FloatV blendV(IntV mask, FloatV a, FloatV b) {  // a where mask is set, else b
    IntV ia, ib;
    std::memcpy(&ia, &a, sizeof a);
    std::memcpy(&ib, &b, sizeof b);
    ia = (ia & mask) | (ib & ~mask);
    std::memcpy(&a, &ia, sizeof a);
    return a;
}
using lanes::sqrtV;
inline void storeV(float* p, FloatV v) { std::memcpy(p, &v, sizeof v); }
// The chord sums' lanes: unsigned, so that they wrap (mod 2^32) as GL's
// atomicAdd does instead of overflowing (undefined for signed integers).
using UintV = std::uint32_t __attribute__((vector_size(sizeof(IntV))));
inline UintV loadU(const std::uint32_t* p) {
    UintV v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void storeU(std::uint32_t* p, UintV v) { std::memcpy(p, &v, sizeof v); }

// Tile-local arrays: rows of kStride floats, the last kLanes - 1 (+1 for
// alignment) padding so that a group of kLanes pixels starting anywhere in the
// row stays inside it; padding lanes are masked off.
constexpr int kStride = kSplatTile + kLanes;
constexpr int kTileN = kSplatTile * kStride;

// One tile of the splat, kLanes pixels of a row at a time in GCC/Clang vector
// types (the projected spheres are only a few pixels wide, so vectorising
// across a row of one sphere is the only way to fill the lanes). Per-pixel ray
// data lives in tile-local arrays (one sqrt per pixel instead of one per
// sphere-pixel pair). Lanes past the sphere's rectangle are masked, not
// branched on. Chords are summed in bin order, a fixed order. The arithmetic
// is the scalar raySphereEyeDepth's, operation for operation. Chords are
// added as fixed-point integers (shared/splat_chords.h), as on GL.
//
// kDiv > 1 (chords only): the output has one pixel per kDiv x kDiv block, its
// ray through the block's centre, and the scene depth of the block is its
// nearest. Tile t then covers the kSplatTile / kDiv square of low-resolution pixels
// under the full-resolution tile t, and the spheres of bin t are tested
// against the low-resolution pixels of their rectangle grown by one full
// pixel: that holds every low-resolution centre inside the projection.
template <bool kDepth, bool kChord, int kDiv = 1, bool kEllipsoid = false>
void splatTile(int t, const Camera& camera, const SplatBins& bins, float radius, const Image<float>* sceneDepth,
               Image<float>* depth, Image<std::uint32_t>* chords) {
    static_assert(kDiv == 1 || (!kDepth && kSplatTile % kDiv == 0));
    const int W = camera.width, H = camera.height;
    const int tx = t % bins.tilesX, ty = t / bins.tilesX;
    // This tile in output pixels (low-resolution ones when kDiv > 1).
    const int bx0 = tx * (kSplatTile / kDiv), by0 = ty * (kSplatTile / kDiv);
    const int bx1 = std::min((W + kDiv - 1) / kDiv, bx0 + kSplatTile / kDiv);
    const int by1 = std::min((H + kDiv - 1) / kDiv, by0 + kSplatTile / kDiv);

    if (bins.start[t] == bins.start[t + 1]) {  // no sphere: nothing but the defaults
        for (int y = by0; y < by1; ++y)
            for (int x = bx0; x < bx1; ++x) {
                if constexpr (kDepth) depth->at(x, y) = kInf;
                if constexpr (kChord) chords->at(x, y) = 0u;  // (x, y) in output pixels
            }
        return;
    }

    // Unit ray u per pixel; eye depth = (ray parameter) * invLen since ray.z = -1.
    alignas(64) float ux[kTileN], uy[kTileN], uz[kTileN], invLen[kTileN];
    alignas(64) float tNear[kTileN], tFar[kTileN];  // near plane and scene, as ray parameters (chord clip)
    alignas(64) float zBest[kTileN];
    alignas(64) std::uint32_t chord[kTileN];  // fixed-point sums
    const float nearM = camera.nearM;
    const float zNear = std::max(nearM, std::numeric_limits<float>::min());
    const float invF = 1.0f / camera.focalPx();
    const float halfW = 0.5f * float(W), halfH = 0.5f * float(H);
    // Setup kLanes pixels at a time, with raySphereEyeDepth's operations.
    // Pixel centres in full-resolution coordinates: kDiv (i + 1/2).
    const FloatV lanesF = FloatV{0.5f, 1.5f, 2.5f, 3.5f} * float(kDiv);
    const float* scene = sceneDepth ? sceneDepth->pixels.data() : nullptr;
    for (int y = 0; y < kSplatTile / kDiv; ++y) {
        const float ry = shared::splatRayY(float(kDiv * (by0 + y)) + 0.5f * float(kDiv), halfH, invF);
        for (int x = 0; x < kStride; x += kLanes) {
            const int j = y * kStride + x;
            const int n = std::min(kLanes, bx1 - bx0 - x);  // pixels of the image in this group
            if (by0 + y >= by1 || n <= 0) {  // padding: finite values, never used
                for (float* a : {ux, uy, uz, invLen, tNear, tFar, zBest}) storeV(a + j, FloatV{});
                storeU(chord + j, UintV{});
                continue;
            }
            const FloatV rx = shared::splatRayX(float(kDiv * (bx0 + x)) + lanesF, halfW, invF);
            const FloatV len = sqrtV(shared::splatRayLength2(rx, FloatV{} + ry));
            FloatV vx, vy, vz, vInvLen;
            shared::splatUnitRay(rx, FloatV{} + ry, len, vx, vy, vz, vInvLen);
            storeV(ux + j, vx);
            storeV(uy + j, vy);
            storeV(uz + j, vz);
            storeV(invLen + j, vInvLen);
            FloatV zScene = FloatV{} + kInf;
            if (scene && kDiv == 1) {
                std::memcpy(&zScene, scene + std::size_t(by0 + y) * W + (bx0 + x), sizeof(float) * n);
            } else if (scene) {
                for (int l = 0; l < n; ++l) {
                    const int fx0 = kDiv * (bx0 + x + l), fy0 = kDiv * (by0 + y);
                    float z = kInf;
                    for (int fy = fy0; fy < std::min(H, fy0 + kDiv); ++fy)
                        for (int fx = fx0; fx < std::min(W, fx0 + kDiv); ++fx) z = std::min(z, scene[std::size_t(fy) * W + fx]);
                    zScene[l] = z;
                }
            }
            storeV(tNear + j, nearM * len);
            storeV(tFar + j, zScene * len);
            // Starting the min at the scene depth discards hits at or behind it
            // (the test is strict); still equal at the end = no fluid.
            storeV(zBest + j, zScene);
            storeU(chord + j, UintV{});
        }
    }

    const float r2 = radius * radius;
    const IntV lane = {0, 1, 2, 3};
    const FloatV inf = FloatV{} + kInf, zero{}, zNearV = FloatV{} + zNear;
    for (std::uint32_t k = bins.start[t]; k < bins.start[t + 1]; ++k) {
        const std::uint32_t i = bins.items[k];
        const PixelRect& rect = bins.rects[i];
        const glm::vec3 c = bins.centres[i];
        const ViewEllipsoid* ell = kEllipsoid ? &bins.ellipsoids[i] : nullptr;
        // The rectangle [x0, x1) holds the full pixels whose centres lie in the
        // projection (or is cut by the image border), so the projection lies in
        // (x0 - 1/2, x1 + 1/2): the low-resolution centres kDiv (i + 1/2) inside
        // that are i in [splatLowBegin(x0), splatLowEnd(x1)).
        const int rx0 = kDiv == 1 ? rect.x0 : shared::splatLowBegin(rect.x0, kDiv);
        const int rx1 = kDiv == 1 ? rect.x1 : shared::splatLowEnd(rect.x1, kDiv);
        const int ry0 = kDiv == 1 ? rect.y0 : shared::splatLowBegin(rect.y0, kDiv);
        const int ry1 = kDiv == 1 ? rect.y1 : shared::splatLowEnd(rect.y1, kDiv);
        const int x0 = std::max(rx0, bx0) - bx0, x1 = std::min(rx1, bx1) - bx0;
        const int y0 = std::max(ry0, by0) - by0, y1 = std::min(ry1, by1) - by0;
        for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; x += kLanes) {
                const int j = y * kStride + x;
                const IntV in = lane < IntV{} + (x1 - x);  // lanes inside the rectangle
                const FloatV vx = detail::loadV(ux + j), vy = detail::loadV(uy + j), vz = detail::loadV(uz + j);
                // b: the ray parameter nearest the centre; the hit spans
                // b -+ sqrt(h2) when h2 >= 0.
                FloatV b, h2;
                if constexpr (kEllipsoid) {
                    shared::rayEllipsoid(vx, vy, vz, ell->m, ell->e, b, h2);
                } else {
                    shared::raySphere(vx, vy, vz, c, r2, b, h2);
                }
                const IntV hit = in & (h2 >= zero);
                const FloatV h = sqrtV(blendV(hit, h2, zero));
                if constexpr (kDepth) {
                    // Nearest hit only; a hit nearer than the near plane is clipped,
                    // not replaced by the exit (zNear > 0 also rejects hits behind the eye).
                    const FloatV zHit = shared::splatHitDepth(b, h, detail::loadV(invLen + j));
                    const FloatV zb = detail::loadV(zBest + j);
                    const FloatV z = blendV(hit & (zHit >= zNearV), zHit, inf);
                    storeV(zBest + j, blendV(z < zb, z, zb));
                }
                if constexpr (kChord) {
                    const FloatV tf = detail::loadV(tFar + j), tn = detail::loadV(tNear + j);
                    const FloatV len = shared::splatChord(b, h, tn, tf);
                    // GL's `if (chord > 0.0) atomicAdd(sum, chordToFixed(chord, r))`:
                    // lanes without a chord convert 0 + 1/2, which truncates to 0.
                    // The units are below 2^31 (clamped), so the signed conversion
                    // is defined and equals the unsigned one.
                    const FloatV units = shared::chordFixedUnits(blendV(hit & (len > zero), len, zero), radius);
                    const UintV fixed = UintV(__builtin_convertvector(units, IntV));
                    storeU(chord + j, loadU(chord + j) + fixed);
                }
            }
        }
    }

    // Write back; still at the scene depth (or +inf) = no fluid.
    const std::size_t outW = std::size_t((W + kDiv - 1) / kDiv);
    for (int y = 0; y < by1 - by0; ++y) {
        const std::size_t row = std::size_t(by0 + y) * outW + bx0;
        for (int x = 0; x < bx1 - bx0; ++x) {
            const int j = y * kStride + x;
            if constexpr (kDepth) {
                const float zScene = scene ? scene[row + x] : kInf;
                depth->pixels[row + x] = zBest[j] < zScene ? zBest[j] : kInf;
            }
            if constexpr (kChord) chords->pixels[row + x] = chord[j];
        }
    }
}

// The default frame's tile (ellipsoids, depth and chords in one pass) compiled
// twice, AVX2 and the SSE2 baseline, picked at run time: the same 4-lane
// operations (no FMA in either), in VEX encoding with AVX2.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default"), flatten))
#endif
void splatTileEllipsoids(int t, const Camera& camera, const SplatBins& bins, float radius,
                         const Image<float>* sceneDepth, Image<float>* depth, Image<std::uint32_t>* chords) {
    splatTile<true, true, 1, true>(t, camera, bins, radius, sceneDepth, depth, chords);
}

template <bool kEllipsoid>
void splatBinsAs(const Camera& camera, const SplatBins& bins, float radius, const Image<float>* sceneDepth,
                 Image<float>* depth, Image<std::uint32_t>* chords) {
    const int tiles = bins.tilesX * bins.tilesY;
    // One task per tile, each writing only its own pixels: thread-count independent.
    auto run = [&](auto kernel) { tbb::parallel_for(0, tiles, [&](int t) { kernel(t); }); };
    if (depth && chords && kEllipsoid)
        run([&](int t) { splatTileEllipsoids(t, camera, bins, radius, sceneDepth, depth, chords); });
    else if (depth && chords)
        run([&](int t) {
            splatTile<true, true, 1, kEllipsoid>(t, camera, bins, radius, sceneDepth, depth, chords);
        });
    else if (depth)
        run([&](int t) {
            splatTile<true, false, 1, kEllipsoid>(t, camera, bins, radius, sceneDepth, depth, chords);
        });
    else if (chords)
        run([&](int t) {
            splatTile<false, true, 1, kEllipsoid>(t, camera, bins, radius, sceneDepth, depth, chords);
        });
}

template <bool kEllipsoid>
void splatChordsLowResAs(const Camera& camera, const SplatBins& bins, float radius, const Image<float>* sceneDepth,
                         int divisor, Image<std::uint32_t>& chords) {
    const int tiles = bins.tilesX * bins.tilesY;
    auto run = [&](auto kernel) { tbb::parallel_for(0, tiles, [&](int t) { kernel(t); }); };
    if (divisor == 2)
        run([&](int t) {
            splatTile<false, true, 2, kEllipsoid>(t, camera, bins, radius, sceneDepth, nullptr, &chords);
        });
    else if (divisor == 4)
        run([&](int t) {
            splatTile<false, true, 4, kEllipsoid>(t, camera, bins, radius, sceneDepth, nullptr, &chords);
        });
    else
        splatBinsAs<kEllipsoid>(camera, bins, radius, sceneDepth, nullptr, &chords);
}

}  // namespace

void splatBins(const Camera& camera, const SplatBins& bins, float radius, const Image<float>* sceneDepth,
               Image<float>* depth, Image<std::uint32_t>* chords) {
    if (bins.ellipsoids.empty()) splatBinsAs<false>(camera, bins, radius, sceneDepth, depth, chords);
    else splatBinsAs<true>(camera, bins, radius, sceneDepth, depth, chords);
}

void splatChordsLowRes(const Camera& camera, const SplatBins& bins, float radius, const Image<float>* sceneDepth,
                       int divisor, Image<std::uint32_t>& chords) {
    if (bins.ellipsoids.empty())
        splatChordsLowResAs<false>(camera, bins, radius, sceneDepth, divisor, chords);
    else
        splatChordsLowResAs<true>(camera, bins, radius, sceneDepth, divisor, chords);
}

Image<float> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                        const Image<float>* sceneDepth, std::span<const EllipsoidShape> shapes) {
    Image<float> depth(camera.width, camera.height, kInf);
    const SplatBins bins = binParticles(camera, positionsWorld, radius, shapes);
    splatBins(camera, bins, radius, sceneDepth, &depth, nullptr);
    return depth;
}

SplatPartial splatPartial(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                          const ThicknessParams& params, const Image<float>* sceneDepth,
                          std::span<const EllipsoidShape> shapes) {
    const int W = camera.width, H = camera.height, d = shared::thicknessDivisor(params.resolutionDivisor);
    SplatPartial partial{Image<float>(W, H), Image<std::uint32_t>((W + d - 1) / d, (H + d - 1) / d)};
    const SplatBins bins = binParticles(camera, positionsWorld, radius, shapes);
    // At full resolution depth and chords share the pass (and the ray hits);
    // on a coarser grid the chords take rays of their own.
    if (d == 1) {
        splatBins(camera, bins, radius, sceneDepth, &partial.depth, &partial.chords);
    } else {
        splatBins(camera, bins, radius, sceneDepth, &partial.depth, nullptr);
        splatChordsLowRes(camera, bins, radius, sceneDepth, d, partial.chords);
    }
    return partial;
}

}  // namespace meniscus::cpu
