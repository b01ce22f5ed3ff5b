// The marching-cubes case table (Lorensen & Cline, SIGGRAPH 1987): for each of
// the 256 inside/outside patterns of a cube's corners, the triangles as
// triples of cube edges. Built once from a rule rather than typed in, so it is
// consistent by construction: on every cube face the crossing points are
// joined the same way whichever cube looks at the face (an ambiguous face, two
// diagonal corners inside, keeps its inside corners apart), so neighbouring
// cubes share their face segments, the mesh has no cracks, and every mesh
// edge lies in exactly two triangles, oriented consistently.
//
// Layout: corner c = x | y << 1 | z << 2 (bit set = +1 along that axis);
// edges 0-3 run along x, 4-7 along y, 8-11 along z; faces 2a + s are the faces
// normal to axis a at side s.
#pragma once

#include <array>
#include <cstdint>

namespace meniscus::surface {

struct McTable {
    // Edge e joins corners edgeCorner[e][0] (the lower one along its axis) and [1].
    std::array<std::array<std::uint8_t, 2>, 12> edgeCorner{};
    std::array<std::uint8_t, 12> edgeAxis{};
    // Triangles of case m (bit c of m set = corner c inside): triangleCount[m]
    // triples of edges in triangles[m], counter-clockwise seen from outside.
    std::array<std::uint8_t, 256> triangleCount{};
    std::array<std::array<std::uint8_t, 36>, 256> triangles{};
    // Bit f of faceCrossed[m]: face f has corners on both sides, so the surface
    // goes on into the neighbour across it.
    std::array<std::uint8_t, 256> faceCrossed{};
};

const McTable& mcTable();

}  // namespace meniscus::surface
