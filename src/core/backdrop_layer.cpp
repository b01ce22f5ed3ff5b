// The backdrop's scene layer (core/backdrop_layer.h).
#include "core/backdrop_layer.h"

#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "shared/backdrop.h"

namespace meniscus {

Status checkBackdropSize(const BackdropImage& backdrop, int width, int height) {
    if (backdrop.width == width && backdrop.height == height) return okStatus();
    return makeError(backdrop.name, "the backdrop is " + std::to_string(backdrop.width) + "x" +
                                        std::to_string(backdrop.height) + " pixels and the picture " +
                                        std::to_string(width) + "x" + std::to_string(height) +
                                        ": render at the backdrop's size (--width " +
                                        std::to_string(backdrop.width) + " --height " +
                                        std::to_string(backdrop.height) + ")");
}

void backdropLayer(const Camera& camera, const BackdropImage& backdrop, Image<glm::vec4>& color,
                   Image<float>& depth) {
    const int W = backdrop.width, H = backdrop.height;
    color = Image<glm::vec4>(W, H);
    depth = Image<float>(W, H);
    const int kind = int(backdrop.convention.kind);
    const float nearM = backdrop.convention.nearM, farM = backdrop.convention.farM;
    const bool hasDepth = backdrop.depth.size() == backdrop.color.size();
    tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                color.at(x, y) = backdrop.color[i];
                const float rayLength = glm::length(camera.pixelRay(float(x) + 0.5f, float(y) + 0.5f));
                depth.at(x, y) = shared::backdropEyeDepth(hasDepth ? backdrop.depth[i] : INFINITY, kind, rayLength,
                                                          nearM, farM);
            }
    });
}

}  // namespace meniscus
