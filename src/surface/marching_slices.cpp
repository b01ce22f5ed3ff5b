#include "surface/marching_slices.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "surface/mc_table.h"
#include "surface/weld.h"

namespace meniscus::surface {

namespace {
constexpr float kUnset = std::numeric_limits<float>::quiet_NaN();
// Vertices keep this fraction of a cube away from the corners, so two
// vertices of one cube never coincide and no triangle is degenerate (the
// surface moves by at most 1/1024 of a cube).
constexpr float kEdgeMargin = 1.0f / 1024.0f;
}  // namespace

BlockMarcher::BlockMarcher(const Grid& grid, const Field& field, float radiusM, std::span<const glm::vec3> positions)
    : grid_(grid), field_(field), radius_(radiusM), positions_(positions), n_(grid.n) {
    slices_.resize(std::size_t(n_) + 1);
    xEdges_.resize(std::size_t(n_) + 1);
    yEdges_.resize(std::size_t(n_) + 1);
    zEdges_.resize(std::size_t(n_));
    todo_.resize(std::size_t(n_));
    sliceZ_.resize(std::size_t(n_) + 1 + LookupCache::kLanes);
}

std::vector<float>& BlockMarcher::slice(int k) {
    auto& s = slices_[std::size_t(k)];
    if (s.empty()) {
        if (!freeList_.empty()) {
            s = std::move(freeList_.back());
            freeList_.pop_back();
        }
        s.assign(std::size_t(n_ + 1) * std::size_t(n_ + 1), kUnset);
        ++liveSlices_;
        firstHeld_ = std::min(firstHeld_, k);
        trackBytes();
    }
    return s;
}

void BlockMarcher::freeSlicesBelow(int k) {
    for (int s = firstHeld_; s < k && s <= n_; ++s) {
        auto& v = slices_[std::size_t(s)];
        if (v.empty()) continue;
        v.clear();
        freeList_.push_back(std::move(v));
        v = {};
        --liveSlices_;
    }
    firstHeld_ = std::max(firstHeld_, k);
}

void BlockMarcher::trackBytes() {
    std::size_t bytes = cache_.bytes() + liveSlices_ * std::size_t(n_ + 1) * std::size_t(n_ + 1) * sizeof(float);
    for (const auto* edges : {&xEdges_, &yEdges_, &zEdges_})
        for (const auto& e : *edges) bytes += e.size() * sizeof(std::int32_t);
    bytes += out_->vertices.size() * (sizeof(glm::vec3) + sizeof(std::uint64_t) + 1) +
             out_->normalSums.size() * sizeof(glm::vec3) +
             out_->triangles.size() * sizeof(std::uint32_t);
    out_->peakBytes = std::max(out_->peakBytes, bytes);
}

void BlockMarcher::evaluate(int i, int j, int k) {
    // Corner k and the next ones up its column in one pass (the walk goes up);
    // one already held gets the same float again.
    float v[LookupCache::kLanes];
    cache_.values(i, j, k, &sliceZ_[std::size_t(k)], v);
    const std::size_t at = std::size_t(j) * std::size_t(n_ + 1) + std::size_t(i);
    const int lanes = std::min(LookupCache::kLanes, n_ + 1 - k);
    for (int q = 0; q < lanes; ++q) slice(k + q)[at] = v[q];
    out_->cornersEvaluated += std::size_t(lanes);
}

float BlockMarcher::corner(int i, int j, int k) {
    const std::size_t at = std::size_t(j) * std::size_t(n_ + 1) + std::size_t(i);
    if (std::isnan(slice(k)[at])) evaluate(i, j, k);
    return slices_[std::size_t(k)][at];
}

std::uint32_t BlockMarcher::vertex(int i, int j, int k, int axis) {
    const std::size_t side = std::size_t(n_ + 1);
    std::vector<std::int32_t>* store;
    std::size_t at;
    if (axis == 0) {
        store = &xEdges_[std::size_t(k)];
        at = std::size_t(j) * std::size_t(n_) + std::size_t(i);
        if (store->empty()) store->assign(std::size_t(n_) * side, -1);
    } else if (axis == 1) {
        store = &yEdges_[std::size_t(k)];
        at = std::size_t(j) * side + std::size_t(i);
        if (store->empty()) store->assign(side * std::size_t(n_), -1);
    } else {
        store = &zEdges_[std::size_t(k)];
        at = std::size_t(j) * side + std::size_t(i);
        if (store->empty()) store->assign(side * side, -1);
    }
    std::int32_t& id = (*store)[at];
    if (id >= 0) return std::uint32_t(id);
    // The crossing on the edge from corner (i,j,k) to the next along `axis`,
    // always interpolated from the lower corner: both blocks of a seam get the
    // same float.
    const int di = axis == 0, dj = axis == 1, dk = axis == 2;
    const float fa = corner(i, j, k), fb = corner(i + di, j + dj, k + dk);
    const int gx = corner0_.x + i, gy = corner0_.y + j, gz = corner0_.z + k;
    const glm::vec3 pa = grid_.corner(gx, gy, gz);
    const glm::vec3 pb = grid_.corner(gx + di, gy + dj, gz + dk);
    const float t = std::clamp((field_.isoRaw - fa) / (fb - fa), kEdgeMargin, 1.0f - kEdgeMargin);
    glm::vec3 p = pa;
    p[axis] = pa[axis] + t * (pb[axis] - pa[axis]);
    id = std::int32_t(out_->vertices.size());
    out_->vertices.push_back(p);
    out_->edgeKeys.push_back(grid_.edgeKey(gx, gy, gz, axis));
    // On a block face: any coordinate across the axis at 0 or n.
    const bool seam = (axis != 0 && (i == 0 || i == n_)) || (axis != 1 && (j == 0 || j == n_)) ||
                      (axis != 2 && (k == 0 || k == n_));
    out_->onSeam.push_back(seam ? 1 : 0);
    return std::uint32_t(id);
}

void BlockMarcher::addCube(int i, int j, int k) {
    if (i < 0 || j < 0 || k < 0 || i >= n_ || j >= n_ || k >= n_) {
        const glm::ivec3 g = corner0_ + glm::ivec3(i, j, k);
        if (g.x >= 0 && g.y >= 0 && g.z >= 0 && g.x < grid_.cubes.x && g.y < grid_.cubes.y && g.z < grid_.cubes.z)
            out_->handoff.push_back(g);
        return;
    }
    if (out_->wasVisited(i, j, k, n_)) return;
    todo_[std::size_t(k)].push_back(std::uint32_t(j) << 16 | std::uint32_t(i));
    lowest_ = std::min(lowest_, k);
}

void BlockMarcher::polygonise(int i, int j, int k) {
    const McTable& t = mcTable();
    float v[8];
    int m = 0;
    for (int c = 0; c < 8; ++c) {
        v[c] = corner(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        if (v[c] >= field_.isoRaw) m |= 1 << c;
    }
    if (m == 0 || m == 255) return;
    ++out_->cubesVisited;
    std::uint32_t ids[12];
    std::uint16_t have = 0;
    for (int e = 0; e < 3 * t.triangleCount[std::size_t(m)]; ++e) {
        const int edge = t.triangles[std::size_t(m)][std::size_t(e)];
        if (!(have & (1u << edge))) {
            const int c0 = t.edgeCorner[std::size_t(edge)][0];
            ids[edge] = vertex(i + (c0 & 1), j + ((c0 >> 1) & 1), k + ((c0 >> 2) & 1), t.edgeAxis[std::size_t(edge)]);
            have = std::uint16_t(have | (1u << edge));
        }
        out_->triangles.push_back(ids[edge]);
    }
    const std::uint8_t faces = t.faceCrossed[std::size_t(m)];
    if (faces & 1) addCube(i - 1, j, k);
    if (faces & 2) addCube(i + 1, j, k);
    if (faces & 4) addCube(i, j - 1, k);
    if (faces & 8) addCube(i, j + 1, k);
    if (faces & 16) addCube(i, j, k - 1);
    if (faces & 32) addCube(i, j, k + 1);
}

void BlockMarcher::run(const Block& block, std::span<const glm::ivec3> extraSeeds, RunMode mode, BlockOutput& out) {
    if (mode == RunMode::Resume) {
        out.handoff.clear();  // the caller has taken the last run's
    } else {
        out = BlockOutput{};
        const std::size_t cubes = std::size_t(n_) * std::size_t(n_) * std::size_t(n_);
        out.visited.assign((cubes + 63) / 64, 0);
    }
    out_ = &out;
    const std::size_t firstIndex = out.triangles.size();
    corner0_ = block.coord * n_;
    firstHeld_ = n_ + 1;
    lowest_ = 0;
    for (std::size_t k = 0; k < sliceZ_.size(); ++k) sliceZ_[k] = grid_.corner(0, 0, corner0_.z + int(k)).z;
    cache_.build(grid_, field_, corner0_, positions_, block.particles);
    trackBytes();

    if (mode == RunMode::Exhaustive) {
        // Validation mode: every cube with corners on both sides is a seed.
        for (int k = 0; k < n_; ++k) {
            for (int j = 0; j < n_; ++j)
                for (int i = 0; i < n_; ++i) {
                    int in = 0;
                    for (int c = 0; c < 8; ++c)
                        in += corner(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)) >= field_.isoRaw;
                    if (in != 0 && in != 8) todo_[std::size_t(k)].push_back(std::uint32_t(j) << 16 | std::uint32_t(i));
                }
            freeSlicesBelow(k);
        }
    } else if (mode == RunMode::Particles) {
        // Vertical walks first; the sideways walks then only where the march
        // from those has not been.
        findWalkers(block);
        walk(true);
    }
    for (const glm::ivec3& g : extraSeeds) addCube(g.x - corner0_.x, g.y - corner0_.y, g.z - corner0_.z);
    march();
    if (mode == RunMode::Particles) {
        walk(false);
        march();
    }
    trackBytes();
    out.cacheEntries += cache_.entries();
    out.cacheRows += cache_.rowsBuilt();
    // Reset the per-block state for the next block.
    freeSlicesBelow(n_ + 1);
    firstHeld_ = n_ + 1;
    for (auto* edges : {&xEdges_, &yEdges_, &zEdges_})
        for (auto& e : *edges) e.clear();
    std::sort(out.handoff.begin(), out.handoff.end(), [](const glm::ivec3& a, const glm::ivec3& b) {
        return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
    });
    out.handoff.erase(std::unique(out.handoff.begin(), out.handoff.end()), out.handoff.end());
    blockNormalSums(out, firstIndex);
    trackBytes();
    out_ = nullptr;
}

// Marching slices: always the lowest slab with work left (a neighbour queued
// below sends the walk back down).
void BlockMarcher::march() {
    BlockOutput& out = *out_;
    lowest_ = 0;
    while (lowest_ < n_) {
        const int k = lowest_;
        auto& list = todo_[std::size_t(k)];
        if (list.empty()) {
            ++lowest_;
            continue;
        }
        freeSlicesBelow(k);
        const std::uint32_t packed = list.back();
        list.pop_back();
        const int i = int(packed & 0xffffu), j = int(packed >> 16);
        const std::size_t b = (std::size_t(k) * std::size_t(n_) + std::size_t(j)) * std::size_t(n_) + std::size_t(i);
        if ((out.visited[b >> 6] >> (b & 63)) & 1u) continue;
        out.visited[b >> 6] |= std::uint64_t(1) << (b & 63);
        polygonise(i, j, k);
    }
}

}  // namespace meniscus::surface
