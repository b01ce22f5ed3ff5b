// CPU triangle-mesh rasteriser: the mesh path's stand-in for smoothing +
// normals, the reference the GL backend's triangle draw is tested against.
//
// Method: half-space (edge-function) rasterisation, Pineda, "A Parallel
// Algorithm for Polygon Rasterization", SIGGRAPH 1988: a pixel centre is inside
// a triangle when the three edge functions E(p) = (b - a) x (p - a) agree in
// sign. Vertices are snapped to 1/256 px and the edge functions evaluated in
// 64-bit integers, exactly; ties (a centre on an edge) follow the top-left rule
// of Direct3D 10+ and GL implementations (an edge owns its centres when it is a
// top or a left edge), so two triangles sharing an edge cover every centre on it
// exactly once. Attributes are interpolated perspective-correctly: 1/w and
// n/w are affine in screen space (Heckbert & Moreton, "Interpolation for
// Polygon Texture Mapping and Shading", 1991), so the eye depth is 1 / (1/w)
// and the normal is the interpolated n/w renormalised; the affine weights are
// the unsnapped triangle's edge functions at the centre over its area.
//
// Clipping is done in view space, where attributes are linear: against the near
// plane (eye depth >= near; a triangle crossing it keeps its front part) and
// against a guard band 2^16 px beyond each image border (so snapped
// coordinates stay within the exact integer range), Sutherland & Hodgman 1974.
// An edge crossing a plane is cut at a point computed from its inside and
// outside vertex in that order, so the two triangles sharing it make the same
// point and stay watertight.
//
// Parallel scheme: triangles are binned to 64 x 64 px tiles in index order and
// each tile is drawn by one task in that order, with a strict z test (the first
// of equal depths wins): bit-identical for any thread count. The bins hold
// indices only and the triangles go in batches of at most kMaxBinEntries bin
// entries, so memory is bounded whatever the mesh.
#include "cpu/raster_mesh.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "shared/raster_mesh.h"
#include "cpu/no_depth.h"

namespace meniscus::cpu {

namespace {

constexpr int kRasterTile = kRasterTilePx;
constexpr std::int64_t kOne = std::int64_t(1) << kRasterSubpixelBits;  // one pixel in fixed point
constexpr std::int64_t kHalf = kOne / 2;                                // pixel centres at +0.5
constexpr double kGuardPx = double(shared::kRasterMaxSidePx);  // guard band beyond each border
// Bin entries (triangle, tile) of one batch: 16 MB of indices.
constexpr std::size_t kMaxBinEntries = std::size_t(1) << 22;
// Triangles looked at per batch (their tile rectangles: 4 MB).
constexpr std::size_t kMaxBatch = std::size_t(1) << 18;
// Clip planes: near, then the guard band's left, right, top, bottom.
constexpr int kPlanes = 5;
// A triangle clipped by five planes has at most 3 + 5 vertices.
constexpr int kMaxPolygon = 3 + kPlanes;

struct Frame {
    int width = 0, height = 0;
    double f = 0.0, halfW = 0.0, halfH = 0.0, nearM = 0.0;
    glm::vec3 right, up, back, eye;
};

// A vertex ready to draw, in two records: what the coverage passes read
// (the rectangles, the bins' tests and the edge functions: 12 bytes) and what
// only the attribute planes and the clipper read, so the passes over every
// triangle stream a sixth of the memory.
struct Fixed {
    std::int32_t fx, fy;   // pixel coordinates (row 0 at the top) * kOne, rounded (when drawable)
    std::uint32_t outside; // bit k: outside clip plane k
};
struct Vertex {
    glm::vec3 view;
    glm::vec3 normal;      // view space, as given (unit for mesh vertices)
    glm::vec2 uv;          // texture coordinates (0 without)
    // When drawable: the unsnapped pixel coordinates (project) and 1/w, made
    // once per vertex for the attributes of every triangle using it.
    double sx, sy, q;
};
// One corner of a triangle to draw: its two records.
struct Corner {
    const Fixed* f;
    const Vertex* v;
};

// Continuous pixel coordinates of a view-space point in front of the eye,
// whose 1/w is q: one division per vertex (q's), the coordinates by products.
inline glm::dvec2 project(const Frame& fr, const glm::vec3& view, double q) {
    return {fr.halfW + fr.f * double(view.x) * q, fr.halfH - fr.f * double(view.y) * q};
}

// Signed distance-like values of a view-space point to the clip planes (>= 0
// inside). Not inlined: the outcodes of the vertices and the clipper's inside
// tests must be the same floats whatever the compiler contracts at a call site.
[[gnu::noinline]] void planeValues(const Frame& fr, const glm::vec3& v, double d[kPlanes]) {
    const double w = -double(v.z), x = fr.f * double(v.x), y = fr.f * double(v.y);
    const double gx = (fr.halfW + kGuardPx) * w, gy = (fr.halfH + kGuardPx) * w;
    d[0] = w - fr.nearM;
    d[1] = gx + x;  // px >= -guard
    d[2] = gx - x;  // px <= W + guard
    d[3] = gy - y;  // py >= -guard
    d[4] = gy + y;  // py <= H + guard
}

// floor(v + 1/2) for |v| < 2^31 (std::llround is a library call).
inline std::int32_t roundToInt(double v) {
    const double r = v + 0.5;
    const auto i = std::int32_t(r);  // truncates toward zero
    return i - std::int32_t(double(i) > r);
}

// The vertex at view-space `view` with `normal`: outcodes and, when inside
// every plane or made by the clipper on one (`onPlane`: rounding may leave it
// an ulp outside), its projection. Not inlined, for the same reason as
// planeValues: a shared vertex is the same bits everywhere.
[[gnu::noinline]] void makeVertex(const Frame& fr, const glm::vec3& view, const glm::vec3& normal,
                                  const glm::vec2& uv, Fixed& f, Vertex& v, bool onPlane = false) {
    v = Vertex{view, normal, uv, 0.0, 0.0, 0.0};
    f = Fixed{0, 0, 0};
    double d[kPlanes];
    planeValues(fr, view, d);
    for (int k = 0; k < kPlanes; ++k) f.outside |= std::uint32_t(d[k] < 0.0) << k;
    if (f.outside == 0 || onPlane) {
        v.q = 1.0 / -double(view.z);
        const glm::dvec2 s = project(fr, view, v.q);
        f.fx = roundToInt(s.x * double(kOne));
        f.fy = roundToInt(s.y * double(kOne));
        v.sx = s.x;
        v.sy = s.y;
    }
}

// The helpers on vectors below are always inlined into the functions over
// lanes, so no vector crosses a call: GCC's note that a 32-byte vector is
// passed differently with AVX does not apply. (It is given at the end of the
// file, so it is off from here to the end.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
// Four doubles and their comparison masks, four 32-bit integers: the vertex
// pass below does four vertices per operation (one AVX2 register, or two SSE2
// ones). Each lane is the IEEE result of its own operands, so the same bits as
// the scalar makeVertex, whose operations it repeats in its order.
typedef double Double4 __attribute__((vector_size(32)));
typedef std::int64_t Mask4 __attribute__((vector_size(32)));
typedef std::int32_t Int4 __attribute__((vector_size(16)));

// roundToInt over four lanes.
[[gnu::always_inline]] inline Int4 roundToInt4(const Double4& v) {
    const Double4 r = v + 0.5;
    const Int4 i = __builtin_convertvector(r, Int4);  // truncates toward zero
    return i + __builtin_convertvector(__builtin_convertvector(i, Double4) > r, Int4);  // mask -1 where rounded up
}

// makeVertex for the mesh's vertices [begin, end), four at a time: view space
// per vertex, then the clip-plane values, the outcodes, the projection (its
// division 1/w four to a register) and the rounding per lane.
// `uvs` may be null (then (0, 0)). No FMA: the lanes' products and sums stay
// separately rounded as in the scalar code.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void makeVertices(const Frame& fr, const glm::vec3* positions, const glm::vec3* normals, const glm::vec2* uvs,
                  std::size_t begin, std::size_t end, Fixed* fixed, Vertex* verts) {
    const double gxScale = fr.halfW + kGuardPx, gyScale = fr.halfH + kGuardPx;
    for (std::size_t i0 = begin; i0 < end; i0 += 4) {
        const int n = int(std::min<std::size_t>(4, end - i0));
        Double4 vx, vy, vz;
        for (int l = 0; l < 4; ++l) {
            const std::size_t i = i0 + std::size_t(std::min(l, n - 1));  // a short block repeats its last
            const glm::vec3 d = positions[i] - fr.eye, nn = normals[i];
            const glm::vec3 view{glm::dot(d, fr.right), glm::dot(d, fr.up), glm::dot(d, fr.back)};
            vx[l] = double(view.x);
            vy[l] = double(view.y);
            vz[l] = double(view.z);
            if (l < n) {
                Vertex& v = verts[i];
                v.view = view;
                v.normal = {glm::dot(nn, fr.right), glm::dot(nn, fr.up), glm::dot(nn, fr.back)};
                v.uv = uvs ? uvs[i] : glm::vec2(0.0f);
            }
        }
        // planeValues
        const Double4 w = -vz, x = fr.f * vx, y = fr.f * vy;
        const Double4 gx = gxScale * w, gy = gyScale * w;
        const Mask4 out = ((w - fr.nearM < 0.0) & 1) | ((gx + x < 0.0) & 2) | ((gx - x < 0.0) & 4) |
                          ((gy - y < 0.0) & 8) | ((gy + y < 0.0) & 16);
        // project, and the rest of makeVertex
        const Double4 q = 1.0 / w;
        const Double4 sx = fr.halfW + x * q, sy = fr.halfH - y * q;
        const Int4 fx = roundToInt4(sx * double(kOne)), fy = roundToInt4(sy * double(kOne));
        for (int l = 0; l < n; ++l) {
            Fixed& f = fixed[i0 + std::size_t(l)];
            Vertex& v = verts[i0 + std::size_t(l)];
            f.outside = std::uint32_t(out[l]);
            const bool drawable = f.outside == 0;
            f.fx = drawable ? fx[l] : 0;
            f.fy = drawable ? fy[l] : 0;
            v.sx = drawable ? sx[l] : 0.0;
            v.sy = drawable ? sy[l] : 0.0;
            v.q = drawable ? q[l] : 0.0;
        }
    }
}

// The part of a triangle to draw, as a convex polygon of drawable vertices.
struct Polygon {
    Fixed f[kMaxPolygon];
    Vertex v[kMaxPolygon];
    int n = 0;
    Corner at(int i) const { return {&f[i], &v[i]}; }
};

// Sutherland-Hodgman against plane k. The cut point of an edge is made from
// (inside vertex, outside vertex) in that order, whichever way the edge runs.
void clipPolygon(const Frame& fr, int k, Polygon& p) {
    Polygon out;
    for (int i = 0; i < p.n; ++i) {
        const Vertex& a = p.v[i];
        const Vertex& b = p.v[(i + 1) % p.n];
        double pa[kPlanes], pb[kPlanes];
        planeValues(fr, a.view, pa);
        planeValues(fr, b.view, pb);
        const double da = pa[k], db = pb[k];
        const bool ina = da >= 0.0, inb = db >= 0.0;
        if (ina) {
            out.f[out.n] = p.f[i];
            out.v[out.n++] = a;
        }
        if (ina != inb) {
            const Vertex& in = ina ? a : b;
            const Vertex& ou = ina ? b : a;
            const double di = ina ? da : db, dout = ina ? db : da;
            const float t = float(di / (di - dout));
            makeVertex(fr, in.view + t * (ou.view - in.view), in.normal + t * (ou.normal - in.normal),
                       in.uv + t * (ou.uv - in.uv), out.f[out.n], out.v[out.n], true);
            ++out.n;
        }
    }
    p = out;
}

// Triangle (a, b, c) clipped to what can be drawn; n < 3 when nothing is left.
void drawablePolygon(const Frame& fr, const Corner& a, const Corner& b, const Corner& c, Polygon& p) {
    p.n = 0;
    if (a.f->outside & b.f->outside & c.f->outside) return;  // wholly outside one plane
    p.f[0] = *a.f;
    p.f[1] = *b.f;
    p.f[2] = *c.f;
    p.v[0] = *a.v;
    p.v[1] = *b.v;
    p.v[2] = *c.v;
    p.n = 3;
    const std::uint32_t any = a.f->outside | b.f->outside | c.f->outside;
    // A plane no vertex is outside of cuts nothing (the planes bound convex
    // half-spaces), so only the planes some vertex is outside of are clipped.
    for (int k = 0; k < kPlanes && p.n >= 3; ++k)
        if (any & (1u << k)) clipPolygon(fr, k, p);
}

// Pixel rectangle [x0, x1) x [y0, y1).
struct Rect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x0 >= x1 || y0 >= y1; }
};

// Smallest pixel index whose centre is at or right of fixed coordinate v:
// floor((v - 1/2 + 1 - 2^-8) px). An arithmetic right shift is floor division
// by a power of two for negative values too (C++20), without a branch.
inline std::int64_t firstCentre(std::int64_t v) { return (v - kHalf + (kOne - 1)) >> kRasterSubpixelBits; }
// Largest pixel index whose centre is at or left of fixed coordinate v: floor(v - 1/2 px).
inline std::int64_t lastCentre(std::int64_t v) { return (v - kHalf) >> kRasterSubpixelBits; }

// The pixels whose centres lie in the fixed-point box [x0, x1] x [y0, y1], cut to the image.
Rect centresIn(const Frame& fr, std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1) {
    Rect r;
    r.x0 = int(std::max<std::int64_t>(0, firstCentre(x0)));
    r.x1 = int(std::min<std::int64_t>(fr.width, lastCentre(x1) + 1));
    r.y0 = int(std::max<std::int64_t>(0, firstCentre(y0)));
    r.y1 = int(std::min<std::int64_t>(fr.height, lastCentre(y1) + 1));
    return r;
}

struct Targets {
    float* depth;               // W x H, starts at the scene depth (or +inf)
    glm::vec3* normal;          // W x H
    glm::vec2* uv;              // W x H or null (no texture coordinates)
    std::uint32_t* coverage;    // W x H or null
    int width;
};

// An edge a -> b of a counter-clockwise (positive-area) triangle: E(p) =
// (b - a) x (p - a), >= 0 inside. The top-left rule: a centre on the edge
// (E = 0) is inside when the edge is a top edge (horizontal, the triangle
// below it: dy = 0, dx > 0 with rows going down) or a left edge (dy < 0);
// the bias makes "inside" one sign test.
struct Edge {
    std::int64_t row, stepX, stepY;  // E at the first centre of the box (biased), per pixel in x, in y
    Edge(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t px, std::int64_t py) {
        const std::int64_t dx = bx - ax, dy = by - ay;
        const bool topLeft = dy < 0 || (dy == 0 && dx > 0);
        row = dx * (py - ay) - dy * (px - ax) - (topLeft ? 0 : 1);
        stepX = -dy * kOne;
        stepY = dx * kOne;
    }
};

// Twice the signed area of the snapped triangle (a, b, c), the edge function of
// a -> b at c: zero when degenerate, its sign the triangle's orientation.
inline std::int64_t snappedArea(const Fixed& a, const Fixed& b, const Fixed& c) {
    return (std::int64_t(b.fx) - a.fx) * (std::int64_t(c.fy) - a.fy) -
           (std::int64_t(b.fy) - a.fy) * (std::int64_t(c.fx) - a.fx);
}

// The pixels whose centres lie in the fixed-point box of (a, b, c), cut to `clip`.
inline Rect centreBox(const Fixed& a, const Fixed& b, const Fixed& c, const Rect& clip) {
    return {int(std::max<std::int64_t>(clip.x0, firstCentre(std::min({a.fx, b.fx, c.fx})))),
            int(std::max<std::int64_t>(clip.y0, firstCentre(std::min({a.fy, b.fy, c.fy})))),
            int(std::min<std::int64_t>(clip.x1, lastCentre(std::max({a.fx, b.fx, c.fx})) + 1)),
            int(std::min<std::int64_t>(clip.y1, lastCentre(std::max({a.fy, b.fy, c.fy})) + 1))};
}

// Per-tile index lists of one batch of triangles, in triangle order.
// Per triangle of a batch, made once by the rectangle pass for the bins and
// the drawing: the pixels whose centres its drawable part's box holds, cut to
// the image (empty: not drawn, also a triangle degenerate after snapping),
// and whether it is drawn whole (its box is then the drawing's box too) or as
// its clipped polygon's fan (x0 stored as ~x0 < 0; each fan triangle's own box
// is made when drawn).
struct Box {
    Rect r;
    bool clipped() const { return r.x0 < 0; }
    Rect pixels() const { return clipped() ? Rect{~r.x0, r.y0, r.x1, r.y1} : r; }
    bool empty() const { return pixels().empty(); }
    Rect tiles() const {
        const Rect p = pixels();
        return {p.x0 / kRasterTile, p.y0 / kRasterTile, (p.x1 - 1) / kRasterTile + 1, (p.y1 - 1) / kRasterTile + 1};
    }
};


[[gnu::always_inline]] inline Int4 min4(const Int4& a, const Int4& b) { return a < b ? a : b; }
[[gnu::always_inline]] inline Int4 max4(const Int4& a, const Int4& b) { return a < b ? b : a; }

// The boxes of triangles [first + k0, first + k1) of a batch (boxes[k] is
// triangle first + k's), four at a time: for a triangle with every vertex
// inside the clip planes its centreBox in the image, or an empty Rect when it
// is degenerate after snapping or has an index out of range. A triangle that
// needs clipping gets an empty Rect and its k is appended to `clipped`, for the
// caller's scalar clipper. The integer arithmetic is the scalar functions' in
// 32 bits: drawable fixed coordinates lie within the guard band, |v| < 2^25,
// so nothing overflows; the snapped area's two products (|.| < 2^52) are exact
// in doubles, so their comparison is the 64-bit one's. (Four lanes, not eight:
// GCC compares eight doubles, two AVX2 registers, one lane at a time.)
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void triangleBoxes(const std::uint32_t* idx, std::size_t nv, const Fixed* fixed, std::size_t first, std::size_t k0,
                   std::size_t k1, int width, int height, Box* boxes, std::vector<std::size_t>& clipped) {
    static const Fixed kNone{0, 0, 0};  // the corners of a triangle with an index out of range: degenerate
    for (std::size_t b0 = k0; b0 < k1; b0 += 4) {
        const int n = int(std::min<std::size_t>(4, k1 - b0));
        Int4 ax, ay, bx, by, cx, cy, out;
        for (int l = 0; l < 4; ++l) {
            const std::size_t t = first + b0 + std::size_t(std::min(l, n - 1));
            const std::uint32_t v0 = idx[3 * t], v1 = idx[3 * t + 1], v2 = idx[3 * t + 2];
            const bool ok = v0 < nv && v1 < nv && v2 < nv;
            const Fixed& a = ok ? fixed[v0] : kNone;
            const Fixed& b = ok ? fixed[v1] : kNone;
            const Fixed& c = ok ? fixed[v2] : kNone;
            ax[l] = a.fx, ay[l] = a.fy, bx[l] = b.fx, by[l] = b.fy, cx[l] = c.fx, cy[l] = c.fy;
            out[l] = std::int32_t(a.outside | b.outside | c.outside);
        }
        const Double4 p = __builtin_convertvector(bx - ax, Double4) * __builtin_convertvector(cy - ay, Double4);
        const Double4 q = __builtin_convertvector(by - ay, Double4) * __builtin_convertvector(cx - ax, Double4);
        const Mask4 degenerate = p == q;
        const Int4 x0 = max4(Int4{} + 0, (min4(ax, min4(bx, cx)) - std::int32_t(kHalf) + std::int32_t(kOne - 1)) >> kRasterSubpixelBits);
        const Int4 y0 = max4(Int4{} + 0, (min4(ay, min4(by, cy)) - std::int32_t(kHalf) + std::int32_t(kOne - 1)) >> kRasterSubpixelBits);
        const Int4 x1 = min4(Int4{} + width, ((max4(ax, max4(bx, cx)) - std::int32_t(kHalf)) >> kRasterSubpixelBits) + 1);
        const Int4 y1 = min4(Int4{} + height, ((max4(ay, max4(by, cy)) - std::int32_t(kHalf)) >> kRasterSubpixelBits) + 1);
        for (int l = 0; l < n; ++l) {
            Box& box = boxes[b0 + std::size_t(l)];
            if (out[l] != 0) {
                box.r = Rect{};
                clipped.push_back(b0 + std::size_t(l));
            } else {
                box.r = degenerate[l] ? Rect{} : Rect{x0[l], y0[l], x1[l], y1[l]};
            }
        }
    }
}

// Draws triangle (a, b, c), drawable vertices of non-zero snapped `area`, at
// the pixel centres of `box` (its centre box cut to the tile, not empty).
// The coverage is the snapped edge functions'; the attributes are
// interpolated perspective-correctly (Heckbert & Moreton 1991) with the
// unsnapped triangle's edge functions at the centre, e_i = its barycentric
// coordinates times its doubled area d (Pineda 1988): with b_i = e_i q_i
// (q = 1/w), 1/w = sum b_i / d, n ~ sum b_i n_i (renormalised: its scale
// drops out) and uv = sum b_i uv_i / sum b_i, so one division and one square
// root per fragment and no division per triangle.
template <bool kCount, bool kUv>
void drawTriangle(Corner a, Corner b, Corner c, std::int64_t area, const Rect& box, const Targets& out) {
    if (area < 0) std::swap(b, c);
    const int x0 = box.x0, x1 = box.x1, y0 = box.y0, y1 = box.y1;
    const std::int64_t px = std::int64_t(x0) * kOne + kHalf, py = std::int64_t(y0) * kOne + kHalf;
    Edge e0(b.f->fx, b.f->fy, c.f->fx, c.f->fy, px, py);  // opposite a
    Edge e1(c.f->fx, c.f->fy, a.f->fx, a.f->fy, px, py);  // opposite b
    Edge e2(a.f->fx, a.f->fy, b.f->fx, b.f->fy, px, py);  // opposite c
    const Vertex &va = *a.v, &vb = *b.v, &vc = *c.v;
    // The unsnapped edges, e_i(p) = k_i + dx_i (p.y - o_i.y) - dy_i (p.x - o_i.x),
    // as k_i + dx_i (p.y - o_i.y) + dy_i o_i.x per row, minus dy_i p.x per centre.
    double dx[3] = {vc.sx - vb.sx, va.sx - vc.sx, vb.sx - va.sx};
    double dy[3] = {vc.sy - vb.sy, va.sy - vc.sy, vb.sy - va.sy};
    const double ox[3] = {vb.sx, vc.sx, va.sx}, oy[3] = {vb.sy, vc.sy, va.sy};
    double d = dx[2] * (vc.sy - va.sy) - dy[2] * (vc.sx - va.sx);
    double k[3] = {0.0, 0.0, 0.0};
    if (d < 0.0) {  // snapping turned the triangle over
        for (int i = 0; i < 3; ++i) dx[i] = -dx[i], dy[i] = -dy[i];
        d = -d;
    }
    if (!(d > 0.0)) {  // degenerate unsnapped: a's values hold across it
        for (int i = 0; i < 3; ++i) dx[i] = dy[i] = 0.0;
        k[0] = d = 1.0;
    }
    const double qa = va.q, qb = vb.q, qc = vc.q;
    // Inside the triangle the eye depth lies between its vertex values; the
    // clamp only catches the extrapolation of centres the snapping let in.
    const double zMin = -double(std::max({va.view.z, vb.view.z, vc.view.z}));
    const double zMax = -double(std::min({va.view.z, vb.view.z, vc.view.z}));
    for (int y = y0; y < y1; ++y) {
        std::int64_t w0 = e0.row, w1 = e1.row, w2 = e2.row;
        const std::size_t rowStart = std::size_t(y) * std::size_t(out.width);
        const double cy = double(y) + 0.5;
        const double ra = k[0] + dx[0] * (cy - oy[0]) + dy[0] * ox[0];
        const double rb = k[1] + dx[1] * (cy - oy[1]) + dy[1] * ox[1];
        const double rc = k[2] + dx[2] * (cy - oy[2]) + dy[2] * ox[2];
        for (int x = x0; x < x1; ++x, w0 += e0.stepX, w1 += e1.stepX, w2 += e2.stepX) {
            if ((w0 | w1 | w2) < 0) continue;  // outside (some biased edge function negative)
            const std::size_t idx = rowStart + std::size_t(x);
            if constexpr (kCount) ++out.coverage[idx];
            const double cx = double(x) + 0.5;
            const double la = ra - dy[0] * cx, lb = rb - dy[1] * cx, lc = rc - dy[2] * cx;
            const double ba = la * qa, bb = lb * qb, bc = lc * qc;
            const double inv = 1.0 / (ba + bb + bc);
            const float z = float(std::clamp(d * inv, zMin, zMax));
            if (!(z < out.depth[idx])) continue;  // strict: the first of equal depths stays
            out.depth[idx] = z;
            const glm::vec3 &na = va.normal, &nb = vb.normal, &nc = vc.normal;
            const double nx = ba * double(na.x) + bb * double(nb.x) + bc * double(nc.x);
            const double ny = ba * double(na.y) + bb * double(nb.y) + bc * double(nc.y);
            const double nz = ba * double(na.z) + bb * double(nb.z) + bc * double(nc.z);
            const double len2 = nx * nx + ny * ny + nz * nz;
            const double s = len2 > 0.0 ? 1.0 / std::sqrt(len2) : 0.0;
            out.normal[idx] = glm::vec3(float(nx * s), float(ny * s), float(nz * s));
            if constexpr (kUv) {
                const glm::vec2 &ua = va.uv, &ub = vb.uv, &uc = vc.uv;
                const double u = ba * double(ua.x) + bb * double(ub.x) + bc * double(uc.x);
                const double v = ba * double(ua.y) + bb * double(ub.y) + bc * double(uc.y);
                out.uv[idx] = glm::vec2(float(u * inv), float(v * inv));
            }
        }
        e0.row += e0.stepY;
        e1.row += e1.stepY;
        e2.row += e2.stepY;
    }
}

struct Bins {
    int tilesX = 0, tilesY = 0;
    std::vector<Box> boxes;             // per triangle of the batch
    std::vector<std::uint32_t> next;    // [slice][tile]: the slice's count, then its fill position
    std::vector<std::uint32_t> start;   // tilesX * tilesY + 1 offsets into items
    std::vector<std::uint32_t> items;   // triangle indices
};

// The bins are filled by fixed slices of a batch, so each bin lists its
// triangles in index order whatever the threads.
constexpr std::size_t kSlices = 16;

std::size_t tileCount(const Box& b) {
    if (b.empty()) return 0;
    const Rect r = b.tiles();
    return std::size_t(r.x1 - r.x0) * std::size_t(r.y1 - r.y0);
}

// Calls fn(slice[tile], k) for every tile of boxes[k], k in [k0, k1).
template <class Fn>
void forTiles(const Bins& bins, std::size_t k0, std::size_t k1, std::uint32_t* slice, Fn&& fn) {
    for (std::size_t k = k0; k < k1; ++k) {
        const Box& b = bins.boxes[k];
        if (b.empty()) continue;
        const Rect r = b.tiles();
        for (int ty = r.y0; ty < r.y1; ++ty)
            for (int tx = r.x0; tx < r.x1; ++tx) fn(slice[std::size_t(ty) * bins.tilesX + tx], k);
    }
}

// Bins triangles [first, first + count) whose boxes are boxes[0..count):
// the kSlices slices of them count their tiles in parallel (already done
// into bins.next by the box pass when `counted`), a prefix sum over (tile,
// slice) gives every slice its range of each bin, and the slices fill them
// in parallel, so every bin lists its triangles in index order.
void fillBins(Bins& bins, std::size_t first, std::size_t count, bool counted) {
    const std::size_t tiles = std::size_t(bins.tilesX) * std::size_t(bins.tilesY);
    auto perSlice = [&](auto&& fn) {
        tbb::parallel_for(std::size_t(0), kSlices, [&](std::size_t s) {
            forTiles(bins, count * s / kSlices, count * (s + 1) / kSlices, &bins.next[s * tiles], fn);
        });
    };
    if (!counted) {
        bins.next.assign(kSlices * tiles, 0);
        perSlice([](std::uint32_t& n, std::size_t) { ++n; });
    }
    bins.start.assign(tiles + 1, 0);
    std::uint32_t total = 0;
    for (std::size_t t = 0; t < tiles; ++t) {
        bins.start[t] = total;
        for (std::size_t s = 0; s < kSlices; ++s) total += std::exchange(bins.next[s * tiles + t], total);
    }
    bins.start[tiles] = total;
    bins.items.resize(total);
    perSlice([&](std::uint32_t& pos, std::size_t k) { bins.items[pos++] = std::uint32_t(first + k); });
}

}  // namespace

struct RasterWorkspace::Data {
    std::vector<Fixed> fixed;
    std::vector<Vertex> verts;
    Bins bins;
};

RasterWorkspace::RasterWorkspace() : data_(std::make_unique<Data>()) {}
RasterWorkspace::~RasterWorkspace() = default;
RasterWorkspace::RasterWorkspace(RasterWorkspace&&) noexcept = default;
RasterWorkspace& RasterWorkspace::operator=(RasterWorkspace&&) noexcept = default;

namespace {

template <bool kCount, bool kUv>
void rasterise(const Frame& fr, const MeshRef& mesh, const Targets& out, RasterWorkspace::Data& work) {
    // Every vertex to view space and the screen once (the workspace's
    // memory reused: a frame of a million vertices does not fault it in again).
    const std::size_t nv = mesh.positions.size();
    std::vector<Fixed>& fixed = work.fixed;
    std::vector<Vertex>& verts = work.verts;
    fixed.resize(nv);
    verts.resize(nv);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        makeVertices(fr, mesh.positions.data(), mesh.normals.data(), kUv ? mesh.uvs.data() : nullptr, r.begin(),
                     r.end(), fixed.data(), verts.data());
    });
    const std::uint32_t* idx = mesh.indices.data();
    // Triangle t's vertex indices, false when one is out of range.
    auto corners = [&](std::size_t t, std::uint32_t v[3]) {
        v[0] = idx[3 * t];
        v[1] = idx[3 * t + 1];
        v[2] = idx[3 * t + 2];
        return v[0] < nv && v[1] < nv && v[2] < nv;
    };
    auto corner = [&](std::uint32_t i) { return Corner{&fixed[i], &verts[i]}; };
    // Calls draw(a, b, c) for each triangle of the fan of t's clipped polygon.
    auto forClipped = [&](std::size_t t, auto&& draw) {
        std::uint32_t v[3];
        if (!corners(t, v)) return;
        Polygon p;
        drawablePolygon(fr, corner(v[0]), corner(v[1]), corner(v[2]), p);
        for (int i = 1; i + 1 < p.n; ++i) draw(p.at(0), p.at(i), p.at(i + 1));
    };

    Bins& bins = work.bins;
    bins.tilesX = (fr.width + kRasterTile - 1) / kRasterTile;
    bins.tilesY = (fr.height + kRasterTile - 1) / kRasterTile;
    const std::size_t triangles = mesh.triangleCount();
    for (std::size_t first = 0; first < triangles;) {
        // Boxes of the next triangles, in parallel.
        const std::size_t look = std::min(kMaxBatch, triangles - first);
        bins.boxes.resize(look);
        std::atomic<std::size_t> lookEntries{0};  // the boxes' bin entries, summed in any order
        const std::size_t tiles = std::size_t(bins.tilesX) * std::size_t(bins.tilesY);
        bins.next.assign(kSlices * tiles, 0);
        // By the bins' slices, which count their boxes' tiles as they go
        // (for fillBins, when the whole look is one batch).
        tbb::parallel_for(std::size_t(0), kSlices, [&](std::size_t s) {
            std::vector<std::size_t> clipped;
            std::size_t entries = 0;
            const std::size_t end = look * (s + 1) / kSlices;
            for (std::size_t k0 = look * s / kSlices; k0 < end; k0 += 4096) {
                const std::size_t k1 = std::min(end, k0 + 4096);
                clipped.clear();
                triangleBoxes(idx, nv, fixed.data(), first, k0, k1, fr.width, fr.height, bins.boxes.data(), clipped);
                for (const std::size_t k : clipped) {
                    std::int64_t x0 = std::numeric_limits<std::int64_t>::max(), y0 = x0, x1 = -x0, y1 = -x0;
                    forClipped(first + k, [&](const Corner& pa, const Corner& pb, const Corner& pc) {
                        for (const Fixed* f : {pa.f, pb.f, pc.f}) {
                            x0 = std::min<std::int64_t>(x0, f->fx);
                            x1 = std::max<std::int64_t>(x1, f->fx);
                            y0 = std::min<std::int64_t>(y0, f->fy);
                            y1 = std::max<std::int64_t>(y1, f->fy);
                        }
                    });
                    const Rect r = x0 <= x1 ? centresIn(fr, x0, y0, x1, y1) : Rect{};
                    if (!r.empty()) bins.boxes[k].r = Rect{~r.x0, r.y0, r.x1, r.y1};
                }
                forTiles(bins, k0, k1, &bins.next[s * tiles], [&](std::uint32_t& n, std::size_t) {
                    ++n;
                    ++entries;
                });
            }
            lookEntries += entries;
        });
        // The batch: as many as fit the bin budget (at least one triangle);
        // all of them unless the sum over them exceeds it.
        std::size_t count = look;
        if (lookEntries.load() > kMaxBinEntries) {
            std::size_t entries = 0;
            for (count = 0; count < look; ++count) {
                const std::size_t c = tileCount(bins.boxes[count]);
                if (count > 0 && entries + c > kMaxBinEntries) break;
                entries += c;
            }
        }
        fillBins(bins, first, count, count == look);
        // One task per tile, each writing only its own pixels, in bin order.
        tbb::parallel_for(0, bins.tilesX * bins.tilesY, [&](int t) {
            if (bins.start[t] == bins.start[t + 1]) return;
            const int tx = t % bins.tilesX, ty = t / bins.tilesX;
            const Rect tile{tx * kRasterTile, ty * kRasterTile, std::min(fr.width, (tx + 1) * kRasterTile),
                            std::min(fr.height, (ty + 1) * kRasterTile)};
            for (std::uint32_t k = bins.start[t]; k < bins.start[t + 1]; ++k) {
                const std::uint32_t tri = bins.items[k];
                const Box& box = bins.boxes[tri - first];
                if (!box.clipped()) {
                    const Rect r{std::max(box.r.x0, tile.x0), std::max(box.r.y0, tile.y0), std::min(box.r.x1, tile.x1),
                                 std::min(box.r.y1, tile.y1)};
                    if (r.empty()) continue;
                    std::uint32_t v[3];
                    corners(tri, v);
                    const Corner a = corner(v[0]), b = corner(v[1]), c = corner(v[2]);
                    drawTriangle<kCount, kUv>(a, b, c, snappedArea(*a.f, *b.f, *c.f), r, out);
                    continue;
                }
                forClipped(tri, [&](const Corner& a, const Corner& b, const Corner& c) {
                    const std::int64_t area = snappedArea(*a.f, *b.f, *c.f);
                    if (area == 0) return;  // degenerate after snapping: covers no centre
                    const Rect r = centreBox(*a.f, *b.f, *c.f, tile);
                    if (!r.empty()) drawTriangle<kCount, kUv>(a, b, c, area, r, out);
                });
            }
        });
        first += count;
    }
}

}  // namespace

MeshRaster rasteriseMesh(const Camera& camera, const TriangleMesh& mesh, const Image<float>* sceneDepth,
                         Image<std::uint32_t>* coverage) {
    MeshRaster out;
    rasteriseMesh(camera, MeshRef::of(mesh), sceneDepth, out, coverage);
    return out;
}

void rasteriseMesh(const Camera& camera, const TriangleMesh& mesh, const Image<float>* sceneDepth, MeshRaster& out,
                   Image<std::uint32_t>* coverage) {
    rasteriseMesh(camera, MeshRef::of(mesh), sceneDepth, out, coverage);
}

void rasteriseMesh(const Camera& camera, const MeshRef& mesh, const Image<float>* sceneDepth, MeshRaster& out,
                   Image<std::uint32_t>* coverage) {
    const int W = camera.width, H = camera.height;
    const bool hasScene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    // The z-buffer starts at the scene depth, so the strict test discards
    // fragments at or behind it; still equal at the end = no fluid. The
    // images are assigned in place (their memory reused when `out` is).
    // Filled a row per task: a 1280 x 720 frame writes 15 MB here.
    const auto refill = [&](auto& image, const auto& value, const float* from = nullptr) {
        image.width = W;
        image.height = H;
        image.pixels.resize(std::size_t(W) * std::size_t(H));
        tbb::parallel_for(tbb::blocked_range<int>(0, H, 16), [&](const tbb::blocked_range<int>& rows) {
            const std::size_t b = std::size_t(rows.begin()) * W, e = std::size_t(rows.end()) * W;
            if constexpr (std::is_same_v<std::decay_t<decltype(value)>, float>)
                if (from) {
                    std::copy(from + b, from + e, image.pixels.begin() + std::ptrdiff_t(b));
                    return;
                }
            std::fill(image.pixels.begin() + std::ptrdiff_t(b), image.pixels.begin() + std::ptrdiff_t(e), value);
        });
    };
    refill(out.depth, kInf, hasScene ? sceneDepth->pixels.data() : nullptr);
    refill(out.normal, glm::vec3(0.0f));
    const bool withUv = !mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size();
    if (withUv) {
        refill(out.uv, glm::vec2(0.0f));
    } else {
        out.uv.width = out.uv.height = 0;
        out.uv.pixels.clear();  // its memory kept for the next textured object
    }
    Frame fr;
    fr.width = W;
    fr.height = H;
    fr.f = double(camera.focalPx());
    fr.halfW = 0.5 * double(W);
    fr.halfH = 0.5 * double(H);
    fr.nearM = double(camera.nearM);
    fr.right = camera.right();
    fr.up = camera.trueUp();
    fr.back = camera.back();
    fr.eye = camera.eye;
    const bool count = coverage && coverage->width == W && coverage->height == H;
    const Targets t{out.depth.pixels.data(), out.normal.pixels.data(), withUv ? out.uv.pixels.data() : nullptr,
                    count ? coverage->pixels.data() : nullptr, W};
    if (mesh.normals.size() == mesh.positions.size() && W > 0 && H > 0) {
        MeshRef m = mesh;
        if (!withUv) m.uvs = {};
        RasterWorkspace::Data& w = out.work.data();
        if (count) withUv ? rasterise<true, true>(fr, m, t, w) : rasterise<true, false>(fr, m, t, w);
        else withUv ? rasterise<false, true>(fr, m, t, w) : rasterise<false, false>(fr, m, t, w);
    }
    if (hasScene)
        tbb::parallel_for(0, H, [&](int y) {
            for (std::size_t i = std::size_t(y) * W; i < std::size_t(y + 1) * W; ++i)
                if (!(out.depth.pixels[i] < sceneDepth->pixels[i])) out.depth.pixels[i] = kInf;
        });
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runRasterise(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    static const TriangleMesh kNoMesh;  // no mesh: no fluid
    auto r = rasteriseMesh(s.camera, s.mesh ? *s.mesh : kNoMesh, &c.scalar(io.at.sceneDepth));
    c.scalarOut(io.at.depth) = std::move(r.depth);
    c.vec3(io.at.normal) = std::move(r.normal);
}

}  // namespace

extern const StageDriver kRasteriseStage = {nullptr, runRasterise};

}  // namespace meniscus::cpu
