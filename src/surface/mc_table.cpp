// Builds the marching-cubes table (see mc_table.h) from one rule per face:
// walking a face's corners counter-clockwise seen from outside the cube, each
// crossing from outside to inside is joined to the next crossing from inside
// to outside. The segments cut off the inside corners of the face (apart, on
// an ambiguous face). Each crossed cube edge starts one segment on one of its
// two faces and ends one on the other, so the segments of a case close into
// loops, triangulated without chords across a face. Seen from outside the fluid they run
// counter-clockwise (tests/surface_test.cpp checks the sign).
#include "surface/mc_table.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

namespace meniscus::surface {

namespace {

glm::vec3 cornerPos(int c) { return glm::vec3(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1)); }

// Triangulates a loop of edge vertices (in order) by clipping ears, never
// with a diagonal between two vertices on one cube face: such a chord lies in
// the face, where the neighbour cube may have the same pair of vertices, and
// the edge would be shared by four triangles. Backtracks; loops have at most
// 12 vertices.
bool triangulate(std::vector<int> loop, const std::array<int, 12>& edgeFaces, std::vector<int>& out) {
    if (loop.size() == 3) {
        out.insert(out.end(), loop.begin(), loop.end());
        return true;
    }
    const std::size_t n = loop.size();
    for (std::size_t i = 0; i < n; ++i) {
        const int a = loop[(i + n - 1) % n], b = loop[i], c = loop[(i + 1) % n];
        if (edgeFaces[std::size_t(a)] & edgeFaces[std::size_t(c)]) continue;  // the chord a-c would lie in a face
        std::vector<int> rest = loop;
        rest.erase(rest.begin() + std::ptrdiff_t(i));
        const std::size_t mark = out.size();
        out.insert(out.end(), {a, b, c});
        if (triangulate(rest, edgeFaces, out)) return true;
        out.resize(mark);
    }
    return false;
}

McTable build() {
    McTable t;
    // Edges: along axis a, the corners without bit a and with it, in a fixed order.
    int e = 0;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 8; ++c)
            if (!(c & (1 << a))) {
                t.edgeCorner[e] = {std::uint8_t(c), std::uint8_t(c | (1 << a))};
                t.edgeAxis[e] = std::uint8_t(a);
                ++e;
            }
    auto edgeOf = [&](int c0, int c1) {
        for (int k = 0; k < 12; ++k)
            if ((t.edgeCorner[k][0] == c0 && t.edgeCorner[k][1] == c1) ||
                (t.edgeCorner[k][0] == c1 && t.edgeCorner[k][1] == c0))
                return k;
        return -1;
    };
    // Faces: the four corners of each, counter-clockwise seen from outside
    // (sorted by angle about the outward normal).
    std::array<std::array<int, 4>, 6> faceCorners{};
    for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
            glm::vec3 n(0.0f);
            n[a] = s ? 1.0f : -1.0f;
            const glm::vec3 u(a == 0 ? 0.0f : 1.0f, a == 0 ? 1.0f : 0.0f, 0.0f);  // any in-plane axis
            const glm::vec3 v = glm::cross(n, u);                                   // u x v = n
            const glm::vec3 centre = 0.5f * glm::vec3(1.0f) + 0.5f * n;
            std::vector<std::pair<float, int>> order;
            for (int c = 0; c < 8; ++c)
                if (((c >> a) & 1) == s) {
                    const glm::vec3 d = cornerPos(c) - centre;
                    order.push_back({std::atan2(glm::dot(d, v), glm::dot(d, u)), c});
                }
            std::sort(order.begin(), order.end());
            for (int i = 0; i < 4; ++i) faceCorners[2 * a + s][i] = order[i].second;
        }

    // The two faces of each edge (bit mask).
    std::array<int, 12> edgeFaces{};
    for (int f = 0; f < 6; ++f)
        for (int i = 0; i < 4; ++i) edgeFaces[std::size_t(edgeOf(faceCorners[f][i], faceCorners[f][(i + 1) % 4]))] |= 1 << f;

    for (int m = 0; m < 256; ++m) {
        auto inside = [&](int c) { return (m >> c) & 1; };
        std::array<int, 12> next;
        next.fill(-1);
        std::uint8_t crossed = 0;
        for (int f = 0; f < 6; ++f) {
            const auto& q = faceCorners[f];
            int in = 0;
            for (int i = 0; i < 4; ++i) in += inside(q[i]);
            if (in == 0 || in == 4) continue;
            crossed |= std::uint8_t(1 << f);
            // Crossings in counter-clockwise order: +1 outside->inside, -1 inside->outside.
            std::vector<std::pair<int, int>> crossings;  // (edge, kind)
            for (int i = 0; i < 4; ++i) {
                const int a = q[i], b = q[(i + 1) % 4];
                if (inside(a) != inside(b)) crossings.push_back({edgeOf(a, b), inside(b) ? +1 : -1});
            }
            for (std::size_t i = 0; i < crossings.size(); ++i)
                if (crossings[i].second == +1) next[crossings[i].first] = crossings[(i + 1) % crossings.size()].first;
        }
        t.faceCrossed[m] = crossed;
        // Close the segments into loops and triangulate each.
        std::array<bool, 12> used{};
        int count = 0;
        for (int start = 0; start < 12; ++start) {
            if (next[start] < 0 || used[start]) continue;
            std::vector<int> loop;
            for (int k = start; !used[k]; k = next[k]) {
                used[k] = true;
                loop.push_back(k);
            }
            std::vector<int> tris;
            const bool ok = triangulate(loop, edgeFaces, tris);
            if (!ok) tris.clear();  // never happens for the 256 cases (tests/surface_test.cpp)
            for (std::size_t k = 0; k < tris.size(); ++k) t.triangles[m][std::size_t(3 * count) + k] = std::uint8_t(tris[k]);
            count += int(tris.size() / 3);
        }
        t.triangleCount[m] = std::uint8_t(count);
    }
    return t;
}

}  // namespace

const McTable& mcTable() {
    static const McTable table = build();
    return table;
}

}  // namespace meniscus::surface
