// CPU depth splat (SPEC §3.3): exact ray-sphere nearest hit per pixel.
#pragma once

#include <span>

#include "meniscus/camera.h"
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
// (when given) are discarded. Output does not depend on the thread count.
Image<float> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                        const Image<float>* sceneDepth = nullptr);

}  // namespace meniscus::cpu
