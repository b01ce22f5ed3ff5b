// CPU compositing of several fluids (docs/pipeline.md#several-fluids; Cords &
// Staadt 2008, "Instant Liquids" §5): the fluids, each splatted, smoothed and
// shaded on its own, joined front to back per pixel. Formulas:
// src/shared/fluids.h.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "meniscus/types.h"

namespace meniscus::cpu {

// One fluid's images, all W x H: its smoothed eye depth (+inf = none), normals,
// thickness, its colour shaded over the scene (cpu::shadeAndComposite) and
// that colour's split into emission E and transmittance T (LayerSplit).
struct FluidLayerImages {
    int fluid = 0;  // its fluid index (the fluid AOV)
    const Image<float>* depth = nullptr;
    const Image<glm::vec3>* normal = nullptr;
    const Image<float>* thickness = nullptr;
    const Image<glm::vec4>* color = nullptr;
    const Image<glm::vec4>* emission = nullptr;
    const Image<glm::vec4>* transmit = nullptr;
};

struct Composited {
    Image<glm::vec4> color;   // the scene where no fluid is drawn, else E_1 + T_1 (... C_m), alpha 1
    Image<float> depth;       // the nearest fluid's eye depth, +inf = none
    Image<glm::vec3> normal;  // the nearest fluid's normal, 0 = none
    Image<float> thickness;   // the sum of the drawn fluids' thicknesses, metres
    Image<float> fluid;       // the nearest fluid's index, -1 = none
};

// Per pixel the fluids drawn there (shared::fluidInFront against `sceneDepth`,
// W x H; null or another size: none), nearest first (equal depths: in the
// order given), composited by shared::fluidOver. `sceneColor` of another size
// counts as transparent black. At most shared::kMaxFluids layers (more are
// ignored). Bit-identical for any thread count.
Composited compositeFluids(std::span<const FluidLayerImages> layers, const Image<glm::vec4>& sceneColor,
                           const Image<float>* sceneDepth);

}  // namespace meniscus::cpu
