// CPU compositing of several fluids, docs/pipeline.md#several-fluids
// (src/shared/fluids.h).
#include "cpu/composite_fluids.h"
#include "cpu/cpu_backend.h"

#include <algorithm>
#include <cmath>

#include "cpu/filter_util.h"
#include "shared/fluids.h"

namespace meniscus::cpu {

Composited compositeFluids(std::span<const FluidLayerImages> layers, const Image<glm::vec4>& sceneColor,
                           const Image<float>* sceneDepth) {
    const int n = std::min(int(layers.size()), shared::kMaxFluids);
    const int w = n > 0 ? layers[0].depth->width : sceneColor.width;
    const int h = n > 0 ? layers[0].depth->height : sceneColor.height;
    const bool hasColor = sceneColor.width == w && sceneColor.height == h;
    const bool hasDepth = sceneDepth && sceneDepth->width == w && sceneDepth->height == h;
    Composited out;
    out.color = Image<glm::vec4>(w, h, glm::vec4(0.0f));
    out.depth = Image<float>(w, h, INFINITY);
    out.normal = Image<glm::vec3>(w, h, glm::vec3(0.0f));
    out.thickness = Image<float>(w, h, 0.0f);
    out.fluid = Image<float>(w, h, -1.0f);
    forEachRow(h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            const float sceneZ = hasDepth ? sceneDepth->pixels[i] : INFINITY;
            // The layers drawn here, sorted nearest first by insertion (stable).
            int order[shared::kMaxFluids];
            float zs[shared::kMaxFluids];
            int m = 0;
            float thickness = 0.0f;
            for (int k = 0; k < n; ++k) {
                const float z = layers[k].depth->pixels[i];
                if (!shared::fluidInFront(z, sceneZ)) continue;
                thickness += layers[k].thickness->pixels[i];
                int j = m++;
                for (; j > 0 && zs[j - 1] > z; --j) {
                    zs[j] = zs[j - 1];
                    order[j] = order[j - 1];
                }
                zs[j] = z;
                order[j] = k;
            }
            if (m == 0) {
                if (hasColor) out.color.pixels[i] = sceneColor.pixels[i];
                continue;
            }
            glm::vec3 acc(layers[order[m - 1]].color->pixels[i]);
            for (int j = m - 2; j >= 0; --j) {
                const FluidLayerImages& l = layers[order[j]];
                acc = shared::fluidOver(glm::vec3(l.emission->pixels[i]), glm::vec3(l.transmit->pixels[i]), acc);
            }
            const FluidLayerImages& front = layers[order[0]];
            out.color.pixels[i] = glm::vec4(acc, 1.0f);
            out.depth.pixels[i] = zs[0];
            out.normal.pixels[i] = front.normal->pixels[i];
            out.thickness.pixels[i] = thickness;
            out.fluid.pixels[i] = float(front.fluid);
        }
    });
    return out;
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Layers 0 .. io.fluids.size() - 1 composited front to back over the scene.
void runCompositeFluids(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    std::vector<FluidLayerImages> layers;
    for (std::size_t i = 0; i < io.fluids.size(); ++i) {
        const int l = int(i);
        layers.push_back({io.fluids[i], &c.scalar(layerSlot(l, LayerImage::Depth)),
                          &c.vec3(layerSlot(l, LayerImage::Normal)), &c.scalar(layerSlot(l, LayerImage::Thickness)),
                          &c.color(layerSlot(l, LayerImage::Color)), &c.color(layerSlot(l, LayerImage::Emission)),
                          &c.color(layerSlot(l, LayerImage::Transmit))});
    }
    Composited out = compositeFluids(layers, c.color(io.at.sceneColor), &c.scalar(io.at.sceneDepth));
    c.colorOut(io.at.color) = std::move(out.color);
    c.scalarOut(io.at.depth) = std::move(out.depth);
    c.vec3(io.at.normal) = std::move(out.normal);
    c.scalarOut(io.at.thickness) = std::move(out.thickness);
    c.scalarOut(io.at.fluidId) = std::move(out.fluid);
}

}  // namespace

extern const StageDriver kCompositeFluidsStage = {nullptr, runCompositeFluids};

}  // namespace meniscus::cpu
