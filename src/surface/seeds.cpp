// Seed cubes from the particles (thesis §4.2.3: "for every particle ... goes
// down from the centre of a particle" until the surface). Walking from every
// particle would cross the whole interior, so only particles at the edge of
// the occupied space walk: the block's particles are binned into cells of the
// rest spacing 2r; for each cell with an empty neighbour cell (not a lone gap
// in the sampling: an empty cell with six occupied neighbours), the particle
// farthest toward that neighbour walks along the grid line nearest to it (a
// margin particle: on the block's face, into the block), toward the empty
// side, until the field crosses the iso level (or, from a particle already
// outside the surface, back toward the fluid). The four cubes around the
// crossed edge are seeds. The vertical walks go first (each column pass
// covers four of their steps) and the march follows their surface; a sideways
// walk then runs only if its path meets no cube the march has taken. A piece
// of surface the walks of one block miss but a neighbour reaches is handed on
// across the seam (extract.cpp), so a block's seeds need only start every
// piece somewhere.
#include <algorithm>
#include <array>
#include <cmath>

#include "surface/marching_slices.h"

namespace meniscus::surface {

namespace {
// The four cubes around the grid edge from corner `lower` along `axis`.
std::array<glm::ivec3, 4> cubesAroundEdge(glm::ivec3 lower, int axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    std::array<glm::ivec3, 4> cubes;
    for (int q = 0; q < 4; ++q) {
        cubes[std::size_t(q)] = lower;
        cubes[std::size_t(q)][b] -= q >> 1;
        cubes[std::size_t(q)][c] -= q & 1;
    }
    return cubes;
}
}  // namespace

void BlockMarcher::seedEdge(glm::ivec3 lower, int axis) {
    for (const glm::ivec3& cube : cubesAroundEdge(lower, axis)) addCube(cube.x, cube.y, cube.z);
}

void BlockMarcher::findWalkers(const Block& block) {
    const float c = grid_.cube;
    const float cell = 2.0f * radius_;
    // Cells over the block and its margin (the block holds every particle within
    // the support of it), in world cell coordinates.
    const glm::vec3 lo = grid_.corner(corner0_.x, corner0_.y, corner0_.z) - (field_.support + 2.0f * c);
    const glm::vec3 hi = grid_.corner(corner0_.x + n_, corner0_.y + n_, corner0_.z + n_) + (field_.support + 2.0f * c);
    const glm::ivec3 c0 = glm::ivec3(glm::floor(lo / cell)) - 1;
    const glm::ivec3 dims = glm::ivec3(glm::floor(hi / cell)) + 2 - c0;
    const std::size_t cells = std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(dims.z);
    auto cellOf = [&](const glm::vec3& p) {
        return glm::clamp(floorToInt(p / cell) - c0, glm::ivec3(0), dims - 1);
    };
    auto cellIndex = [&](glm::ivec3 q) {
        return (std::size_t(q.z) * std::size_t(dims.y) + std::size_t(q.y)) * std::size_t(dims.x) + std::size_t(q.x);
    };
    std::vector<std::uint8_t> occupied(cells, 0);
    for (std::uint32_t id : block.particles) occupied[cellIndex(cellOf(positions_[id]))] = 1;
    // An empty cell whose six neighbours are all occupied is a gap in the
    // sampling inside the liquid, not a side to walk to (walks toward it
    // would cross no surface, at full length).
    auto hole = [&](glm::ivec3 q) {
        for (int d = 0; d < 6; ++d) {
            glm::ivec3 nb = q;
            nb[d / 2] += (d & 1) ? 1 : -1;
            if (nb[d / 2] < 0 || nb[d / 2] >= dims[d / 2] || !occupied[cellIndex(nb)]) return false;
        }
        return true;
    };

    // The walker per (cell, direction): the particle farthest that way. A
    // particle of the margin (its centre outside the block along one axis)
    // walks only along that axis, into the block: that is how a surface whose
    // particles all lie in a neighbour reaches into this block.
    constexpr int kNone = -1;
    std::vector<std::int32_t>& walker = walker_;
    walker.assign(cells * 6, kNone);
    for (std::uint32_t id : block.particles) {
        const glm::vec3 p = positions_[id];
        const glm::ivec3 g = floorToInt(p / c) - grid_.origin - corner0_;  // its cube, block-local
        int outsideAxis = -1, outsideCount = 0, intoBlock = 0;
        for (int a = 0; a < 3; ++a)
            if (g[a] < 0 || g[a] >= n_) {
                outsideAxis = a;
                ++outsideCount;
                intoBlock = g[a] < 0 ? 1 : 0;  // direction bit: 1 = toward +
            }
        if (outsideCount > 1) continue;
        const glm::ivec3 q = cellOf(p);
        for (int d = 0; d < 6; ++d) {
            if (outsideCount == 1 && d != 2 * outsideAxis + intoBlock) continue;
            glm::ivec3 nb = q;
            nb[d / 2] += (d & 1) ? 1 : -1;
            if (nb[d / 2] < 0 || nb[d / 2] >= dims[d / 2] || occupied[cellIndex(nb)]) continue;
            if (hole(nb)) continue;
            std::int32_t& w = walker[cellIndex(q) * 6 + std::size_t(d)];
            const float sign = (d & 1) ? 1.0f : -1.0f;
            if (w == kNone || sign * p[d / 2] > sign * positions_[std::uint32_t(w)][d / 2] ||
                (p[d / 2] == positions_[std::uint32_t(w)][d / 2] && std::int32_t(id) < w))
                w = std::int32_t(id);
        }
    }

    walks_.clear();
    for (std::size_t at = 0; at < walker.size(); ++at)
        if (walker[at] != kNone) walks_.push_back({std::uint32_t(walker[at]), std::uint8_t(at % 6)});
}

// Any of the four cubes around the grid edge from `lower` along `axis` visited?
bool BlockMarcher::visitedAround(glm::ivec3 lower, int axis) const {
    for (const glm::ivec3& cube : cubesAroundEdge(lower, axis))
        if (cube.x >= 0 && cube.y >= 0 && cube.z >= 0 && cube.x < n_ && cube.y < n_ && cube.z < n_ &&
            out_->wasVisited(cube.x, cube.y, cube.z, n_))
            return true;
    return false;
}

void BlockMarcher::walk(bool vertical) {
    const float c = grid_.cube;
    const int steps = int(std::ceil((4.0f * radius_ + field_.support) / c)) + 1;
    for (const Walk& w : walks_) {
        const int d = w.direction, axis = d / 2;
        if ((axis == 2) != vertical) continue;
        const glm::vec3 p = positions_[w.particle];
        // The nearest grid corner, clamped into the block: a particle of the
        // margin walks on the block's face, where a surface that reaches into
        // this block from a neighbour's particles crosses.
        const glm::ivec3 start = glm::clamp(floorToInt(p / c + 0.5f) - grid_.origin - corner0_,
                                            glm::ivec3(0), glm::ivec3(n_));
        if (!vertical) {
            // A sideways walk whose path toward the empty side meets a cube the
            // march has already polygonised would find a piece already taken.
            const int toward = (d & 1) ? 1 : -1;
            bool taken = false;
            glm::ivec3 q = start;
            for (int s = 0; s < steps && !taken; ++s) {
                glm::ivec3 next = q;
                next[axis] += toward;
                if (next[axis] < 0 || next[axis] > n_) break;
                glm::ivec3 lower = q;
                lower[axis] = std::min(q[axis], next[axis]);
                taken = visitedAround(lower, axis);
                q = next;
            }
            if (taken) continue;
        }
        ++out_->seedWalks;
        const float f0 = corner(start.x, start.y, start.z);
        const bool in0 = f0 >= field_.isoRaw;
        // From inside: toward the empty side; from outside: back into the fluid.
        const int step = ((d & 1) ? 1 : -1) * (in0 ? 1 : -1);
        glm::ivec3 q = start;
        for (int s = 0; s < steps; ++s) {
            glm::ivec3 next = q;
            next[axis] += step;
            if (next[axis] < 0 || next[axis] > n_) break;
            const bool in = corner(next.x, next.y, next.z) >= field_.isoRaw;
            if (in != in0) {
                glm::ivec3 lower = q;
                lower[axis] = std::min(q[axis], next[axis]);
                seedEdge(lower, axis);
                break;
            }
            q = next;
        }
    }
}

}  // namespace meniscus::surface
