// The sprites of the particles near the smoothed surface
// (docs/pipeline.md#noise-and-foam), binned into screen tiles: what the surface
// noise (surface_noise.cpp) and the velocity whitening (velocity_map.cpp)
// splat. The culling and the sprite's geometry are
// src/shared/surface_noise.h's, shared with the GL twin.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/types.h"
#include "shared/surface_noise.h"

namespace meniscus::cpu {

inline constexpr int kSpriteTilePx = 32;

struct SurfaceSprites {
    int tilesX = 0, tilesY = 0;
    // Per particle (all of them; only those listed in `items` count).
    std::vector<shared::NoiseSprite> sprite;
    std::vector<float> weight;  // A_i exp(-(delta / falloff)^2)
    // Per tile t, the indices of the counted particles whose sprite touches it:
    // items[start[t] .. start[t + 1]), in particle order.
    std::vector<std::uint32_t> start, items;
};

// Every particle in front of the near plane whose sprite (spriteRadii r) is on
// the image with its centre, and whose weight against `depth` (the smoothed
// eye depth; falloffRadii r) with amplitude[i] (empty: 1) is at least
// shared::kNoiseMinWeight.
SurfaceSprites findSurfaceSprites(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                  const Image<float>& depth, std::span<const float> amplitude, float spriteRadii,
                                  float falloffRadii);

// Bins rectangles (x0, y0, x1, y1; non-empty where on[i]) into kSpriteTilePx
// tiles: per tile t the indices i of the rectangles touching it,
// items[start[t] .. start[t + 1]), in index order.
void binIntoTiles(std::span<const glm::ivec4> rects, std::span<const std::uint8_t> on, int tilesX, int tilesY,
                  std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& items);

// Pixel rectangle [x0, x1) x [y0, y1) of tile t.
glm::ivec4 spriteTileRect(const SurfaceSprites& s, std::size_t t, int width, int height);

}  // namespace meniscus::cpu
