// Checks the scene geometry tests share (geometry_test.cpp, io_geometry_test.cpp):
// a closed, consistently oriented surface and outward unit normals.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <tuple>

#include "meniscus/mesh.h"

namespace meniscus::test {

// Every edge (by its end points' positions, so per-face vertices count as one
// corner) is used by exactly two triangles, once in each direction: a closed
// surface whose triangles all wind the same way.
inline void expectClosedAndOriented(const TriangleMesh& m) {
    auto key = [&](std::uint32_t i) {
        const glm::vec3& p = m.positions[i];
        // Quantised to a micrometre: coincident corners of different faces match.
        return std::array<long, 3>{std::lround(p.x * 1e6f), std::lround(p.y * 1e6f), std::lround(p.z * 1e6f)};
    };
    std::map<std::pair<std::array<long, 3>, std::array<long, 3>>, int> edges;
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) ++edges[{key(m.indices[t + e]), key(m.indices[t + (e + 1) % 3])}];
    for (const auto& [edge, count] : edges) {
        EXPECT_EQ(count, 1) << "a directed edge used " << count << " times";
        const auto back = edges.find({edge.second, edge.first});
        EXPECT_TRUE(back != edges.end() && back->second == 1) << "an edge without its opposite";
        if (::testing::Test::HasFailure()) return;
    }
}

// Unit normals, pointing away from `centre` (a convex shape around it), and
// every triangle's own normal (from its winding) too.
inline void expectOutward(const TriangleMesh& m, const glm::vec3& centre) {
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(m.normals[i]), 1.0f, 1e-5f) << "vertex " << i;
        EXPECT_GT(glm::dot(m.normals[i], m.positions[i] - centre), 0.0f) << "vertex " << i;
    }
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
        EXPECT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f - centre), 0.0f) << "triangle " << t / 3;
    }
}

}  // namespace meniscus::test
