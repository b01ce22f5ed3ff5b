// Anisotropic kernels, Yu & Turk 2013 (anisotropy.h). Per particle, in one
// pass over its neighbourhood: the weighted mean offset mu (their eq. 10,
// relative to the particle so nothing large cancels), the weighted
// covariance C = E_w[d d^T] - mu mu^T (eq. 9), its eigen-decomposition
// C = R diag(s1, s2, s3) R^T, the axes (eq. 13, volume-preserving, see
// AnisotropyParams) and the smoothed centre x + lambda mu (eq. 6).
//
// The neighbour search: a dense grid over the bounds (core/dense_grid.h; the
// hashed grid of core/hash_grid.h when far outliers would make it too
// large) with cells of R, walked cell by cell: the candidates of the 3^3
// cells around a cell, as ranges of the sorted points, serve all of that
// cell's particles. Per particle, a first pass packs the offsets of the
// candidates within R (about 33 of 220 in the bulk), a second sums over
// them alone; the eigen solve then runs four particles at a time in double
// lanes. The sums run in the grid's fixed order and every lane's result
// depends on its own particle only, so the result does not depend on the
// thread count; the AVX2 and the baseline code do the same IEEE operations,
// so it does not depend on the CPU either.
#include "core/anisotropy.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/dense_grid.h"
#include "core/hash_grid.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif



namespace meniscus {

namespace {

// The helpers on vectors below are always inlined into the functions over
// lanes, so no vector crosses a call: GCC's note that a 32-byte vector is
// passed differently with AVX does not apply (off from here to the end).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
// The neighbour passes run over eight candidates at a time, in GCC vector
// types: one AVX register where the CPU has AVX2, two SSE registers on the
// baseline (each loop is compiled for both, picked at run time). Both do the same IEEE
// operations in the same lanes (no FMA), so the bits are the same on every
// x86-64 machine.
constexpr int kLanes = 8;
using F8 = float __attribute__((vector_size(4 * kLanes)));
using I8 = std::int32_t __attribute__((vector_size(4 * kLanes)));
// The eigen solve runs four particles at a time in double lanes.
using D4 = double __attribute__((vector_size(32)));
using M4 = std::int64_t __attribute__((vector_size(32)));
constexpr float kFar = 1e18f;  // padding: |d|^2 ~ 3e36 stays finite, outside any R
__attribute__((always_inline)) inline double hsum(F8 v) {
    return ((double(v[0]) + double(v[1])) + (double(v[2]) + double(v[3]))) +
           ((double(v[4]) + double(v[5])) + (double(v[6]) + double(v[7])));
}

// Lane-wise IEEE square roots (correctly rounded, as std::sqrt): two SSE
// halves (split and joined in registers), or one AVX instruction.
struct SqrtBase {
    __attribute__((always_inline)) static F8 apply(F8 v) {
#if defined(__SSE__)
        using H = float __attribute__((vector_size(16)));
        const H lo = H(_mm_sqrt_ps(__m128(__builtin_shufflevector(v, v, 0, 1, 2, 3))));
        const H hi = H(_mm_sqrt_ps(__m128(__builtin_shufflevector(v, v, 4, 5, 6, 7))));
        return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
#else
        for (int l = 0; l < kLanes; ++l) v[l] = std::sqrt(v[l]);
        return v;
#endif
    }
    __attribute__((always_inline)) static D4 apply(D4 v) {
#if defined(__SSE2__)
        using H = double __attribute__((vector_size(16)));
        const H lo = H(_mm_sqrt_pd(__m128d(__builtin_shufflevector(v, v, 0, 1))));
        const H hi = H(_mm_sqrt_pd(__m128d(__builtin_shufflevector(v, v, 2, 3))));
        return __builtin_shufflevector(lo, hi, 0, 1, 2, 3);
#else
        for (int l = 0; l < 4; ++l) v[l] = std::sqrt(v[l]);
        return v;
#endif
    }
};
// The AVX2 copies are GCC's: Clang refuses to pass a 32-byte vector to the
// AVX2 square root from the templates, which are not themselves compiled for
// AVX2 (GCC inlines it first). Clang builds (the sanitizer build) take the
// baseline code, which gives the same bits (Anisotropy.BaselineAndAvx2CodeGiveTheSameBits).
#if (defined(__x86_64__) || defined(__i386__)) && !defined(__clang__)
#define MENISCUS_ANISOTROPY_AVX2 1
struct SqrtAvx2 {
    // Not always_inline: GCC inlines it once the loop sits in the AVX2 function.
    __attribute__((target("avx2"))) static F8 apply(F8 v) { return F8(_mm256_sqrt_ps(__m256(v))); }
    __attribute__((target("avx2"))) static D4 apply(D4 v) { return D4(_mm256_sqrt_pd(__m256d(v))); }
};
#endif

// A matrix from its unit axes (columns of r) and values along them: r diag(v) r^T.
// Symmetric: each of the 6 distinct entries once.
glm::mat3 fromAxes(const glm::dmat3& r, const glm::dvec3& v) {
    glm::mat3 out;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            out[i][j] = out[j][i] =
                float((v[0] * (r[0][i] * r[0][j]) + v[1] * (r[1][i] * r[1][j])) + v[2] * (r[2][i] * r[2][j]));
    return out;
}

}  // namespace

EllipsoidShape sphereShape(float radius) {
    return {glm::mat3(1.0f / radius), glm::mat3(radius * radius)};
}

EllipsoidShape scaledShape(const EllipsoidShape& shape, float scale) {
    return {shape.m * (1.0f / scale), shape.q * (scale * scale)};
}

EllipsoidShape ellipsoidShape(const glm::mat3& axes, const glm::vec3& a) {
    const glm::dmat3 r(axes);
    const glm::dvec3 ad(a);
    return {fromAxes(r, 1.0 / ad), fromAxes(r, ad * ad)};
}

namespace {

__attribute__((always_inline)) inline D4 vmax(D4 a, D4 b) { return a < b ? b : a; }  // std::max, lane by lane
__attribute__((always_inline)) inline D4 vmin(D4 a, D4 b) { return b < a ? b : a; }  // std::min
__attribute__((always_inline)) inline D4 vabs(D4 a) { return a < 0.0 ? -a : a; }
struct V3 {
    D4 x, y, z;
};
__attribute__((always_inline)) inline V3 operator*(D4 s, const V3& v) { return {s * v.x, s * v.y, s * v.z}; }
__attribute__((always_inline)) inline V3 operator+(const V3& a, const V3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
__attribute__((always_inline)) inline D4 dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
__attribute__((always_inline)) inline V3 cross(const V3& a, const V3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
__attribute__((always_inline)) inline V3 select(M4 m, const V3& a, const V3& b) { return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z}; }

// The eigen-decomposition of four symmetric matrices at once, one per lane
// (a: xx, xy, xz, yy, yz, zz): every lane takes the same operations, the
// special cases are lane selections, so a lane's result does not depend on
// the others. See symmetricEigen (anisotropy.h) for what it returns.
template <class Sqrt>
__attribute__((always_inline)) inline void eigenLanesT(const D4* a, D4* values, V3* vectors) {
    const D4 a00 = a[0], a01 = a[1], a02 = a[2], a11 = a[3], a12 = a[4], a22 = a[5];
    // Eigenvalues in closed form (O. K. Smith, "Eigenvalues of a symmetric
    // 3 x 3 matrix", CACM 4(4) 1961): with q = tr(a)/3 and p the scale of
    // a - qI, B = (a - qI)/p has eigenvalues 2 cos(phi + 2 pi k / 3), where
    // cos(3 phi) = det(B) / 2.
    const D4 p1 = a01 * a01 + a02 * a02 + a12 * a12;
    const D4 q = (a00 + a11 + a22) / 3.0;
    const D4 d0 = a00 - q, d1 = a11 - q, d2 = a22 - q;
    const D4 p = Sqrt::apply((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * p1) / 6.0);
    const D4 scale = vmax(vmax(vmax(vabs(a00), vabs(a11)), vmax(vabs(a22), Sqrt::apply(p1))), D4{} + 1e-300);
    const M4 identity = ~(p > 1e-12 * scale);  // a multiple of the identity: any frame
    const D4 ip = 1.0 / p;
    const D4 b00 = d0 * ip, b11 = d1 * ip, b22 = d2 * ip, b01 = a01 * ip, b02 = a02 * ip, b12 = a12 * ip;
    const D4 det = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
    const D4 r = identity ? D4{} : vmax(vmin(det * 0.5, D4{} + 1.0), D4{} - 1.0);
    // phi in [0, pi/3]; cos(phi + 2 pi/3) = -(cos phi + sqrt 3 sin phi) / 2,
    // with sin phi >= 0 from cos phi (where the root loses digits, phi ~ 0,
    // e3 is the one next to e2 and is recomputed below from the 2 x 2 problem).
    D4 cphi;
    for (int l = 0; l < 4; ++l) cphi[l] = std::cos(std::acos(r[l]) / 3.0);
    const D4 sphi = Sqrt::apply(vmax(1.0 - cphi * cphi, D4{}));
    constexpr double kSqrt3 = 1.7320508075688772935;
    const D4 e1 = q + 2.0 * p * cphi, e3 = q - p * (cphi + kSqrt3 * sphi), e2 = 3.0 * q - e1 - e3;  // e1 >= e2 >= e3
    // Eigenvectors (after J. Kopp, "Efficient numerical diagonalization of
    // hermitian 3x3 matrices", 2008): the one of the eigenvalue farthest from
    // the middle one (it is simple) as the longest cross product of two rows
    // of a - lambda I (they span its orthogonal complement); the other two by
    // diagonalising a in the plane orthogonal to it (a 2 x 2 rotation).
    const M4 firstApart = (e1 - e2) >= (e2 - e3);
    const D4 lambda = firstApart ? e1 : e3;
    const V3 r0{a00 - lambda, a01, a02}, r1{a01, a11 - lambda, a12}, r2{a02, a12, a22 - lambda};
    const V3 c0 = cross(r0, r1), c1 = cross(r0, r2), c2 = cross(r1, r2);
    const D4 n0 = dot(c0, c0), n1 = dot(c1, c1), n2 = dot(c2, c2);
    const M4 take1 = n1 > n0;
    V3 best = select(take1, c1, c0);
    D4 len2 = take1 ? n1 : n0;
    const M4 take2 = n2 > len2;
    best = select(take2, c2, best), len2 = take2 ? n2 : len2;
    const M4 notSimple = ~(len2 > 1e-20 * scale * scale * scale * scale);  // any frame
    const V3 v = (1.0 / Sqrt::apply(len2)) * best;
    // A unit vector orthogonal to v, and a third.
    const M4 smallX = vabs(v.x) < 0.6;
    const V3 t{smallX ? D4{} : -v.z, smallX ? v.z : D4{}, smallX ? -v.y : v.x};  // v x e_x or v x e_y
    const V3 u = (1.0 / Sqrt::apply(dot(t, t))) * t, w = cross(v, u);
    auto times = [&](const V3& x) __attribute__((always_inline)) {
        return V3{a00 * x.x + a01 * x.y + a02 * x.z, a01 * x.x + a11 * x.y + a12 * x.z,
                  a02 * x.x + a12 * x.y + a22 * x.z};
    };
    const V3 au = times(u), aw = times(w);
    const D4 auu = dot(u, au), auw = dot(u, aw), aww = dot(w, aw);
    // The rotation by theta with tan(2 theta) = 2 auw / (auu - aww)
    // diagonalises [[auu, auw], [auw, aww]]: theta = atan2(2 auw, auu - aww) / 2
    // in (-pi/2, pi/2], its cosine and sine from the double angle's by the
    // half-angle formulas.
    const D4 c2x = auu - aww, s2x = 2.0 * auw, h = Sqrt::apply(c2x * c2x + s2x * s2x);
    const D4 ih = 1.0 / h;
    const D4 cos2 = c2x * ih, sin2 = s2x * ih;
    const D4 cA = Sqrt::apply(0.5 * (1.0 + cos2)), sA = sin2 / (2.0 * cA);         // cos 2 theta >= 0
    const D4 sB0 = Sqrt::apply(0.5 * (1.0 - cos2)), cB0 = sin2 / (2.0 * sB0);      // < 0
    const M4 negative = M4(sin2) < 0;                                               // its sign bit: theta < 0
    const M4 firstForm = cos2 >= 0.0, turn = h > 0.0;
    const D4 c = turn ? (firstForm ? cA : (negative ? -cB0 : cB0)) : D4{} + 1.0;
    const D4 s = turn ? (firstForm ? sA : (negative ? -sB0 : sB0)) : D4{};
    const V3 x = c * u + s * w, y = (-s) * u + c * w;  // eigenvalues: the larger along x
    const D4 ex = dot(x, times(x)), ey = dot(y, times(y));
    const M4 swap = ex < ey;
    const V3 big = select(swap, y, x), small = select(swap, x, y);
    const D4 eBig = vmax(ex, ey), eSmall = vmin(ex, ey);
    values[0] = firstApart ? e1 : eBig, values[1] = firstApart ? eBig : eSmall, values[2] = firstApart ? eSmall : e3;
    vectors[0] = select(firstApart, v, big), vectors[1] = select(firstApart, big, small);
    vectors[2] = select(firstApart, small, v);
    const M4 left = dot(cross(vectors[0], vectors[1]), vectors[2]) < 0.0;  // make it right-handed
    vectors[2] = select(left, (D4{} - 1.0) * vectors[2], vectors[2]);
    const M4 anyFrame = identity | notSimple;
    const D4 zero{}, one = zero + 1.0;
    vectors[0] = select(anyFrame, V3{one, zero, zero}, vectors[0]);
    vectors[1] = select(anyFrame, V3{zero, one, zero}, vectors[1]);
    vectors[2] = select(anyFrame, V3{zero, zero, one}, vectors[2]);
    for (int k = 0; k < 3; ++k) values[k] = identity ? q : (notSimple ? (k == 0 ? e1 : k == 1 ? e2 : e3) : values[k]);
}
void eigenLanesBase(const D4* a, D4* values, V3* vectors) { eigenLanesT<SqrtBase>(a, values, vectors); }
#if MENISCUS_ANISOTROPY_AVX2
__attribute__((target("avx2"))) void eigenLanesAvx2(const D4* a, D4* values, V3* vectors) {
    eigenLanesT<SqrtAvx2>(a, values, vectors);
}
const bool kCpuHasAvx2 = __builtin_cpu_supports("avx2");
std::atomic<bool> gAllowAvx2{true};
bool useAvx2() { return kCpuHasAvx2 && gAllowAvx2.load(std::memory_order_relaxed); }
#endif
void eigenLanes(const D4* a, D4* values, V3* vectors) {
#if MENISCUS_ANISOTROPY_AVX2
    if (useAvx2()) return eigenLanesAvx2(a, values, vectors);
#endif
    eigenLanesBase(a, values, vectors);
}

}  // namespace

void symmetricEigen(const glm::dmat3& a, glm::dvec3& values, glm::dmat3& vectors) {
    // Lane 0 of the four-lane solve (the same bits as in computeAnisotropy).
    const D4 zero{};
    const D4 in[6] = {zero + a[0][0], zero + 0.5 * (a[0][1] + a[1][0]), zero + 0.5 * (a[0][2] + a[2][0]),
                      zero + a[1][1], zero + 0.5 * (a[1][2] + a[2][1]), zero + a[2][2]};
    D4 v[3];
    V3 r[3];
    eigenLanes(in, v, r);
    values = glm::dvec3(v[0][0], v[1][0], v[2][0]);
    for (int k = 0; k < 3; ++k) vectors[k] = glm::dvec3(r[k].x[0], r[k].y[0], r[k].z[0]);
}

namespace {

// The weighted mean offset of a flat half-space's neighbourhood, in units of
// R: with w = 1 - (d/R)^3, E_w[d cos theta] over the half ball =
// (1/2) (R^4/4 - R^4/7) / (R^3/3 - R^3/6) / R = 9/28.
constexpr double kHalfSpaceOffset = 9.0 / 28.0;

// A run [b, e) of candidates in the sorted coordinate arrays.
struct Span {
    std::uint32_t b, e;
};

// The weighted sums of one particle's neighbourhood (d = x_j - x_i):
// W = sum w, s = sum w d, c = sum w d d^T (xx, xy, xz, yy, yz, zz), and
// how many candidates lie within R (the particle itself included).
struct Sums {
    double W, s[3], c[6];
    int count;
};

// One particle's neighbours, in two passes over its candidates. First the
// offsets d = x_j - x_i of the candidates within R, packed in candidate
// order into `near` (three arrays of `cap` floats: x, y, z; each pass-one
// vector writes all its lanes, so cap >= candidates + kLanes); then the
// weighted sums over those alone (|d|^2 again, and the square root of the
// weight only for them: about 33 of 220 candidates in the bulk), lane by lane in
// float, lane = position in `near` mod kLanes, added up in a fixed order.
// The packing is the same in both builds (AVX2: a permutation from a table
// per lane mask; baseline: lane by lane), and so are the sums.
struct Near {
    float* v;  // x[cap], y[cap], z[cap]
    std::size_t cap;
};

__attribute__((always_inline)) inline I8 laneIndex() {
    I8 l;
    for (int k = 0; k < kLanes; ++k) l[k] = k;
    return l;
}

// The first pass, baseline: returns how many candidates lie within R.
std::uint32_t packNearBase(const float* xs, const float* ys, const float* zs, const Span* spans, int spanCount,
                           const glm::vec3& p, float R2, const Near& near) {
    float* nx = near.v;
    float* ny = nx + near.cap;
    float* nz = ny + near.cap;
    std::uint32_t n = 0;
    const I8 lane = laneIndex();
    for (int r = 0; r < spanCount; ++r) {
        const std::uint32_t b = spans[r].b, e = spans[r].e;
        for (std::uint32_t k = b; k < e; k += kLanes) {
            F8 dx, dy, dz;
            std::memcpy(&dx, xs + k, sizeof dx);
            std::memcpy(&dy, ys + k, sizeof dy);
            std::memcpy(&dz, zs + k, sizeof dz);
            dx -= p.x, dy -= p.y, dz -= p.z;
            const F8 d2 = dx * dx + dy * dy + dz * dz;
            const I8 in = (d2 < R2) & (lane < std::int32_t(e - k));
            std::uint64_t words[4];
            std::memcpy(words, &in, sizeof words);
            if ((words[0] | words[1] | words[2] | words[3]) == 0) continue;  // most vectors: none within R
            for (int l = 0; l < kLanes; ++l) {
                nx[n] = dx[l], ny[n] = dy[l], nz[n] = dz[l];
                n += std::uint32_t(in[l] & 1);
            }
        }
    }
    return n;
}

#if MENISCUS_ANISOTROPY_AVX2
// For each 8-bit lane mask, the lanes set, in order, as a permutation.
struct PackTable {
    alignas(32) std::int32_t perm[256][8];
    PackTable() {
        for (int m = 0; m < 256; ++m) {
            int n = 0;
            for (int l = 0; l < 8; ++l)
                if (m & (1 << l)) perm[m][n++] = l;
            while (n < 8) perm[m][n++] = 0;
        }
    }
};
const PackTable kPack;

// The first pass, AVX2: the same offsets (the same operations in the same
// order, no FMA), packed with a permutation.
__attribute__((target("avx2"))) std::uint32_t packNearAvx2(const float* xs, const float* ys, const float* zs,
                                                           const Span* spans, int spanCount, const glm::vec3& p,
                                                           float R2, const Near& near) {
    float* nx = near.v;
    float* ny = nx + near.cap;
    float* nz = ny + near.cap;
    std::uint32_t n = 0;
    const __m256 px = _mm256_set1_ps(p.x), py = _mm256_set1_ps(p.y), pz = _mm256_set1_ps(p.z);
    const __m256 r2 = _mm256_set1_ps(R2);
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (int r = 0; r < spanCount; ++r) {
        const std::uint32_t b = spans[r].b, e = spans[r].e;
        for (std::uint32_t k = b; k < e; k += kLanes) {
            const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(xs + k), px);
            const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(ys + k), py);
            const __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(zs + k), pz);
            const __m256 d2 =
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
            const __m256 valid = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(std::int32_t(e - k)), lane));
            const int mask = _mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(d2, r2, _CMP_LT_OQ), valid));
            const __m256i perm = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.perm[mask]));
            _mm256_storeu_ps(nx + n, _mm256_permutevar8x32_ps(dx, perm));
            _mm256_storeu_ps(ny + n, _mm256_permutevar8x32_ps(dy, perm));
            _mm256_storeu_ps(nz + n, _mm256_permutevar8x32_ps(dz, perm));
            n += std::uint32_t(__builtin_popcount(unsigned(mask)));
        }
    }
    return n;
}
#endif

// The second pass: the sums over the n packed neighbours.
template <class Sqrt>
__attribute__((always_inline)) inline void nearSumsT(const Near& near, std::uint32_t n, float invR3, Sums& out) {
    const float* nx = near.v;
    const float* ny = nx + near.cap;
    const float* nz = ny + near.cap;
    F8 W{}, sx{}, sy{}, sz{}, sxx{}, sxy{}, sxz{}, syy{}, syz{}, szz{};
    const I8 lane = laneIndex();
    for (std::uint32_t k = 0; k < n; k += kLanes) {
        F8 dx, dy, dz;
        std::memcpy(&dx, nx + k, sizeof dx);
        std::memcpy(&dy, ny + k, sizeof dy);
        std::memcpy(&dz, nz + k, sizeof dz);
        const F8 d2 = dx * dx + dy * dy + dz * dz;  // as the first pass has it
        const I8 in = lane < std::int32_t(n - k);
        // Past n: the lanes' offsets are zeroed (packNear's caller), their weights masked.
        const F8 w = F8(I8(1.0f - d2 * Sqrt::apply(d2) * invR3) & in);  // 1 - (|d| / R)^3 (Yu & Turk eq. 11)
        const F8 wx = w * dx, wy = w * dy, wz = w * dz;
        W += w, sx += wx, sy += wy, sz += wz;
        sxx += wx * dx, sxy += wx * dy, sxz += wx * dz;
        syy += wy * dy, syz += wy * dz, szz += wz * dz;
    }
    out.count = int(n);
    out.W = hsum(W);
    out.s[0] = hsum(sx), out.s[1] = hsum(sy), out.s[2] = hsum(sz);
    out.c[0] = hsum(sxx), out.c[1] = hsum(sxy), out.c[2] = hsum(sxz);
    out.c[3] = hsum(syy), out.c[4] = hsum(syz), out.c[5] = hsum(szz);
}
void nearSumsBase(const Near& near, std::uint32_t n, float invR3, Sums& out) {
    nearSumsT<SqrtBase>(near, n, invR3, out);
}
#if MENISCUS_ANISOTROPY_AVX2
__attribute__((target("avx2"))) void nearSumsAvx2(const Near& near, std::uint32_t n, float invR3, Sums& out) {
    nearSumsT<SqrtAvx2>(near, n, invR3, out);
}
#endif

// Before the first passes of a cell's particles: its candidates within
// `reach` of the box [lo, hi] around them, their coordinates packed in
// candidate order into `near` (so the first passes see the same candidates
// in the same order, less those that cannot be within R of any particle of
// the cell, in one range); returns how many.
std::uint32_t packBoxBase(const float* xs, const float* ys, const float* zs, const Span* spans, int spanCount,
                          const glm::vec3& lo, const glm::vec3& hi, float reach2, const Near& near) {
    float* nx = near.v;
    float* ny = nx + near.cap;
    float* nz = ny + near.cap;
    std::uint32_t n = 0;
    const I8 lane = laneIndex();
    for (int r = 0; r < spanCount; ++r) {
        const std::uint32_t b = spans[r].b, e = spans[r].e;
        for (std::uint32_t k = b; k < e; k += kLanes) {
            F8 x, y, z;
            std::memcpy(&x, xs + k, sizeof x);
            std::memcpy(&y, ys + k, sizeof y);
            std::memcpy(&z, zs + k, sizeof z);
            const F8 gx = lo.x - x > x - hi.x ? lo.x - x : x - hi.x;  // > 0 outside
            const F8 gy = lo.y - y > y - hi.y ? lo.y - y : y - hi.y;
            const F8 gz = lo.z - z > z - hi.z ? lo.z - z : z - hi.z;
            const F8 ex = F8(I8(gx) & (gx > 0.0f)), ey = F8(I8(gy) & (gy > 0.0f)), ez = F8(I8(gz) & (gz > 0.0f));
            const I8 in = (ex * ex + ey * ey + ez * ez < reach2) & (lane < std::int32_t(e - k));
            for (int l = 0; l < kLanes; ++l) {
                nx[n] = x[l], ny[n] = y[l], nz[n] = z[l];
                n += std::uint32_t(in[l] & 1);
            }
        }
    }
    return n;
}
#if MENISCUS_ANISOTROPY_AVX2
__attribute__((target("avx2"))) std::uint32_t packBoxAvx2(const float* xs, const float* ys, const float* zs,
                                                          const Span* spans, int spanCount, const glm::vec3& lo,
                                                          const glm::vec3& hi, float reach2, const Near& near) {
    float* nx = near.v;
    float* ny = nx + near.cap;
    float* nz = ny + near.cap;
    std::uint32_t n = 0;
    const __m256 lx = _mm256_set1_ps(lo.x), ly = _mm256_set1_ps(lo.y), lz = _mm256_set1_ps(lo.z);
    const __m256 hx = _mm256_set1_ps(hi.x), hy = _mm256_set1_ps(hi.y), hz = _mm256_set1_ps(hi.z);
    const __m256 r2 = _mm256_set1_ps(reach2), zero = _mm256_setzero_ps();
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    for (int r = 0; r < spanCount; ++r) {
        const std::uint32_t b = spans[r].b, e = spans[r].e;
        for (std::uint32_t k = b; k < e; k += kLanes) {
            const __m256 x = _mm256_loadu_ps(xs + k), y = _mm256_loadu_ps(ys + k), z = _mm256_loadu_ps(zs + k);
            const __m256 ex = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(lx, x), _mm256_sub_ps(x, hx)), zero);
            const __m256 ey = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(ly, y), _mm256_sub_ps(y, hy)), zero);
            const __m256 ez = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(lz, z), _mm256_sub_ps(z, hz)), zero);
            const __m256 d2 =
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ex, ex), _mm256_mul_ps(ey, ey)), _mm256_mul_ps(ez, ez));
            const __m256 valid = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(std::int32_t(e - k)), lane));
            const int mask = _mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(d2, r2, _CMP_LT_OQ), valid));
            const __m256i perm = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPack.perm[mask]));
            _mm256_storeu_ps(nx + n, _mm256_permutevar8x32_ps(x, perm));
            _mm256_storeu_ps(ny + n, _mm256_permutevar8x32_ps(y, perm));
            _mm256_storeu_ps(nz + n, _mm256_permutevar8x32_ps(z, perm));
            n += std::uint32_t(__builtin_popcount(unsigned(mask)));
        }
    }
    return n;
}
#endif
std::uint32_t packBox(const float* xs, const float* ys, const float* zs, const Span* spans, int spanCount,
                      const glm::vec3& lo, const glm::vec3& hi, float reach2, const Near& near) {
    std::uint32_t n;
#if MENISCUS_ANISOTROPY_AVX2
    if (useAvx2())
        n = packBoxAvx2(xs, ys, zs, spans, spanCount, lo, hi, reach2, near);
    else
#endif
        n = packBoxBase(xs, ys, zs, spans, spanCount, lo, hi, reach2, near);
    for (int a = 0; a < 3; ++a) std::fill_n(near.v + a * near.cap + n, kLanes, kFar);
    return n;
}

// Both passes for the particle at p.
void neighbourSums(const float* xs, const float* ys, const float* zs, const Span* spans, int spanCount,
                   const glm::vec3& p, float R2, float invR3, const Near& near, Sums& out) {
    std::uint32_t n;
#if MENISCUS_ANISOTROPY_AVX2
    if (useAvx2())
        n = packNearAvx2(xs, ys, zs, spans, spanCount, p, R2, near);
    else
#endif
        n = packNearBase(xs, ys, zs, spans, spanCount, p, R2, near);
    for (int a = 0; a < 3; ++a) std::fill_n(near.v + a * near.cap + n, kLanes, 0.0f);
#if MENISCUS_ANISOTROPY_AVX2
    if (useAvx2()) return nearSumsAvx2(near, n, invR3, out);
#endif
    nearSumsBase(near, n, invR3, out);
}

// One particle's ellipsoid from its neighbourhood's sums, in two steps
// around the eigen solve, which runs four particles at a time.
struct Pca {
    float R2, invR3;
    const AnisotropyParams& params;

    // A particle waiting for its eigen solve.
    struct Pending {
        std::uint32_t i;  // input index
        float radius;     // its own radius (its volume, and its size alone)
        glm::dvec3 mu;    // weighted mean offset
    };

    // The centre; a lone particle's sphere (returns true); else its
    // covariance (xx, xy, xz, yy, yz, zz) into lane `lane` of cov.
    bool prepare(const glm::vec3& p, const Sums& sums, Pending& pending, glm::vec3& centre, EllipsoidShape& shape,
                 D4* cov, int lane) const {
        const double Wd = sums.W;  // >= 1: the particle itself
        const double inv = 1.0 / Wd;
        const glm::dvec3 mu = glm::dvec3(sums.s[0], sums.s[1], sums.s[2]) * inv;
        centre = glm::vec3(glm::dvec3(p) + double(params.smoothing) * mu);  // Yu & Turk eq. 6
        if (sums.count - 1 < params.minNeighbours) {
            shape = sphereShape(params.kn * pending.radius);
            return true;
        }
        pending.mu = mu;
        // Yu & Turk eq. 9, about the weighted mean.
        cov[0][lane] = sums.c[0] * inv - mu.x * mu.x, cov[1][lane] = sums.c[1] * inv - mu.x * mu.y;
        cov[2][lane] = sums.c[2] * inv - mu.x * mu.z, cov[3][lane] = sums.c[3] * inv - mu.y * mu.y;
        cov[4][lane] = sums.c[4] * inv - mu.y * mu.z, cov[5][lane] = sums.c[5] * inv - mu.z * mu.z;
        return false;
    }

    // The shapes of up to four particles from their eigen-decompositions
    // (lane l: sigma descending, unit axes), lane by lane in double; the
    // result of each, and whether it counts as isolated, at its index.
    void finish(const Pending* pending, int count, const D4* sigma, const V3* axes, glm::vec3* centres,
                EllipsoidShape* shapes, std::uint8_t* isolated) const {
        D4 radius, mux, muy, muz;
        for (int l = 0; l < 4; ++l) {
            const Pending& at = pending[l < count ? l : 0];
            radius[l] = at.radius, mux[l] = at.mu.x, muy[l] = at.mu.y, muz[l] = at.mu.z;
        }
        // Yu & Turk eq. 13: the smaller axes at least 1/kr of the largest;
        // then the volume of the sphere of radius r.
        const D4 floor = sigma[0] / double(params.kr);
        const D4 s1 = vmax(sigma[1], floor), s2 = vmax(sigma[2], floor);
        const D4 volume = sigma[0] * s1 * s2;
        D4 k;
        for (int l = 0; l < 4; ++l) k[l] = radius[l] / std::cbrt(volume[l]);
        const D4 a[3] = {sigma[0] * k, s1 * k, s2 * k};
        const D4 inv[3] = {1.0 / a[0], 1.0 / a[1], 1.0 / a[2]};
        const D4 sq[3] = {a[0] * a[0], a[1] * a[1], a[2] * a[2]};
        // m = R diag(1/a) R^T and q = R diag(a^2) R^T, each distinct entry once.
        auto component = [&](const V3& v, int i) { return i == 0 ? v.x : i == 1 ? v.y : v.z; };
        D4 m[3][3], q[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = i; j < 3; ++j) {
                D4 e[3];
                for (int c = 0; c < 3; ++c) e[c] = component(axes[c], i) * component(axes[c], j);
                m[i][j] = m[j][i] = (inv[0] * e[0] + inv[1] * e[1]) + inv[2] * e[2];
                q[i][j] = q[j][i] = (sq[0] * e[0] + sq[1] * e[1]) + sq[2] * e[2];
            }
        // At a free surface the neighbours' mean lies inward along the
        // shortest axis; the flattened ellipsoid would end a - a.z short of
        // the sphere's outer side. Move it out by that much, scaled by how
        // one-sided the neighbourhood is (a flat half-space's mean offset is
        // kHalfSpaceOffset R; a sheet's or the bulk's is ~0).
        const D4 along = mux * axes[2].x + muy * axes[2].y + muz * axes[2].z;
        const D4 t = vmin(vabs(along) / (kHalfSpaceOffset * std::sqrt(double(R2))), D4{} + 1.0);
        const D4 f = (along > 0.0 ? D4{} - 1.0 : D4{} + 1.0) * t * (radius - a[2]);
        const M4 move = a[2] < radius;
        for (int l = 0; l < count; ++l) {
            const std::uint32_t i = pending[l].i;
            if (!(sigma[0][l] > 0.0)) {  // all neighbours on the particle itself
                shapes[i] = sphereShape(params.kn * pending[l].radius);
                isolated[i] = 1;
                continue;
            }
            EllipsoidShape& shape = shapes[i];
            for (int c = 0; c < 3; ++c)
                for (int r = 0; r < 3; ++r) shape.m[c][r] = float(m[c][r][l]), shape.q[c][r] = float(q[c][r][l]);
            if (params.keepSurface && move[l])
                centres[i] += glm::vec3(glm::dvec3(f[l] * axes[2].x[l], f[l] * axes[2].y[l], f[l] * axes[2].z[l]));
            isolated[i] = 0;
        }
    }
};

}  // namespace

void computeAnisotropy(std::span<const glm::vec3> positions, float radius, const AnisotropyParams& params,
                       Ellipsoids& out, std::span<const float> radii) {
    const std::size_t n = positions.size();
    out.centres.resize(n);
    out.shapes.resize(n);
    out.isolated = 0;
    if (n == 0) return;
    const float R = params.neighbourRadii * radius;
    const Pca pca{R * R, 1.0f / (R * R * R), params};
    const bool own = radii.size() == n;
    std::vector<std::uint8_t> isolated(n, 0);
    // Cells of R: the 3^3 cells around a particle's hold its neighbourhood.
    // The points in cell order as plain arrays (padded for whole-vector
    // loads), and per cell the ranges of its candidates, once for all its
    // particles. (Cells of R/2 scan fewer candidates, 5^3/8 of the volume
    // instead of 27, but in 25 short ranges per cell: measured slower, 56 ms
    // against 48 ms at R = 5 r on frame 21 with 2 threads.)
    std::vector<float> xs, ys, zs;
    // The box test keeps every candidate the exact test |d|^2 < R^2 could
    // take: R widened by far more than the float rounding of the coordinates.
    glm::vec3 lo(positions[0]), hi(positions[0]);
    for (const glm::vec3& x : positions) lo = glm::min(lo, x), hi = glm::max(hi, x);
    float maxAbs = 0.0f;
    for (int a = 0; a < 3; ++a) maxAbs = std::max({maxAbs, std::abs(lo[a]), std::abs(hi[a])});
    const float reach = R * 1.001f + 1e-5f * maxAbs;
    const float boxReach2 = reach * reach;
    auto run = [&](std::size_t cells, const std::vector<glm::vec3>& pts, const std::vector<std::uint32_t>& order,
                   auto&& ranges, auto&& range) {
        xs.assign(pts.size() + kLanes, kFar), ys.assign(pts.size() + kLanes, kFar), zs.assign(pts.size() + kLanes, kFar);
        for (std::size_t k = 0; k < pts.size(); ++k) xs[k] = pts[k].x, ys[k] = pts[k].y, zs[k] = pts[k].z;
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const auto& block) {
            std::vector<Span> spans;
            std::vector<float> buffer, cell;
            // Up to four particles waiting for the eigen solve.
            Pca::Pending pending[4];
            D4 cov[6] = {};
            int waiting = 0;
            auto solve = [&] {
                D4 sigma[3];
                V3 axes[3];
                eigenLanes(cov, sigma, axes);
                pca.finish(pending, waiting, sigma, axes, out.centres.data(), out.shapes.data(), isolated.data());
                waiting = 0;
            };
            for (std::size_t c = block.begin(); c != block.end(); ++c) {
                const auto [b, e] = range(c);
                if (b == e) continue;
                spans.clear();
                ranges(c, spans);
                std::size_t candidates = 0;
                for (const Span& s : spans) candidates += s.e - s.b;
                const std::size_t cap = candidates + 2 * kLanes;
                if (buffer.size() < 3 * cap) buffer.resize(3 * cap);
                const Near near{buffer.data(), cap};
                // With a few particles, the candidates near their box first.
                const float* cx = xs.data();
                const float* cy = ys.data();
                const float* cz = zs.data();
                Span one;
                const Span* use = spans.data();
                int useCount = int(spans.size());
                if (e - b >= 3) {
                    glm::vec3 lo = pts[b], hi = pts[b];
                    for (std::uint32_t s = b + 1; s < e; ++s) lo = glm::min(lo, pts[s]), hi = glm::max(hi, pts[s]);
                    if (cell.size() < 3 * cap) cell.resize(3 * cap);
                    const Near box{cell.data(), cap};
                    one = {0, packBox(xs.data(), ys.data(), zs.data(), spans.data(), int(spans.size()), lo, hi,
                                      boxReach2, box)};
                    cx = box.v, cy = box.v + cap, cz = box.v + 2 * cap;
                    use = &one, useCount = 1;
                }
                for (std::uint32_t s = b; s < e; ++s) {
                    const std::uint32_t i = order[s];
                    Sums sums;
                    neighbourSums(cx, cy, cz, use, useCount, pts[s], pca.R2, pca.invR3, near, sums);
                    Pca::Pending& next = pending[waiting];
                    next.i = i, next.radius = own ? radii[i] : radius;
                    if (pca.prepare(pts[s], sums, next, out.centres[i], out.shapes[i], cov, waiting)) {
                        isolated[i] = 1;
                    } else if (++waiting == 4) {
                        solve();
                    }
                }
            }
            if (waiting > 0) {
                for (int l = waiting; l < 4; ++l)
                    for (D4& v : cov) v[l] = v[0];
                solve();
            }
        });
    };
    using Spans = std::vector<Span>;
    detail::DenseGrid dense;
    if (dense.build(positions, R, 8 * n + (std::size_t(1) << 20))) {
        // Dense: a row of three cells is one range of points.
        run(
            dense.cellCount(), dense.points(), dense.order(),
            [&](std::size_t c, Spans& near) {
                dense.forRowsNear(dense.coords(c), 1, [&](std::uint32_t b, std::uint32_t e) {
                    if (b < e) near.push_back({b, e});
                });
            },
            [&](std::size_t c) { return std::pair(dense.begin(c), dense.begin(c + 1)); });
    } else {
        // Far outliers: the hashed grid (only occupied cells exist).
        const detail::HashGrid grid(positions, double(R), glm::dvec3(positions[0]));
        run(
            grid.cellCount(), grid.points(), grid.order(),
            [&](std::size_t c, Spans& near) {
                const detail::HashGrid::Key key = grid.cellKey(c);
                for (int z = -1; z <= 1; ++z)
                    for (int y = -1; y <= 1; ++y)
                        for (int x = -1; x <= 1; ++x)
                            grid.forCellRange({key[0] + x, key[1] + y, key[2] + z},
                                              [&](std::uint32_t b, std::uint32_t e) { near.push_back({b, e}); });
            },
            [&](std::size_t c) { return std::pair(grid.cellBegin(c), grid.cellEnd(c)); });
    }
    for (std::uint8_t v : isolated) out.isolated += v;
}

namespace detail {
bool allowAnisotropyAvx2(bool allow) {
#if MENISCUS_ANISOTROPY_AVX2
    return gAllowAvx2.exchange(allow);
#else
    (void)allow;
    return false;
#endif
}
}  // namespace detail

std::string checkAnisotropyParams(const AnisotropyParams& p) {
    if (!(p.neighbourRadii >= 2.0f && p.neighbourRadii <= 16.0f)) return "neighbourRadii: 2 to 16 particle radii";
    if (!(p.kr >= 1.0f && p.kr <= 16.0f)) return "kr: 1 to 16";
    if (!(p.kn > 0.0f && p.kn <= 1.0f)) return "kn: above 0, at most 1";
    if (p.minNeighbours < 0 || p.minNeighbours > 1000) return "minNeighbours: 0 to 1000";
    if (!(p.smoothing >= 0.0f && p.smoothing <= 1.0f)) return "smoothing: 0 to 1";
    return {};
}

}  // namespace meniscus
