// The stage order of the screen-space pipeline (SPEC §1), in one place.
// Implemented so far: depth splat -> depth view. Smoothing, normals, thickness
// and shading are the next stages to arrive here.
#include <algorithm>
#include <cmath>
#include <limits>

#include "cpu/splat.h"
#include "meniscus/renderer.h"

namespace meniscus {

namespace {

// A person-readable picture of eye depth: near = bright, far = dark, over the
// depth range of the fluid in view; no fluid = dark background, A = coverage.
Image<glm::vec4> depthView(const Image<float>& depth) {
    float zmin = std::numeric_limits<float>::infinity(), zmax = 0.0f;
    for (float z : depth.pixels)
        if (std::isfinite(z)) {
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
        }
    const float span = zmax > zmin ? zmax - zmin : 1.0f;
    Image<glm::vec4> out(depth.width, depth.height, glm::vec4(0.02f, 0.02f, 0.025f, 0.0f));
    for (std::size_t i = 0; i < depth.size(); ++i) {
        const float z = depth.pixels[i];
        if (!std::isfinite(z)) continue;
        const float s = 1.0f - 0.85f * (z - zmin) / span;  // 1 at the nearest fluid, 0.15 at the farthest
        out.pixels[i] = glm::vec4(s * s * glm::vec3(0.85f, 0.92f, 1.0f), 1.0f);
    }
    return out;
}

}  // namespace

Result<Aovs> renderFrame(std::span<const glm::vec3> positions, const RenderSettings& s) {
    if (auto st = validateCamera(s.camera); !st) return st.error();
    if (!(s.radiusM > 0.0f) || !std::isfinite(s.radiusM))
        return makeError("", "particle radius must be a positive number of metres");

    Aovs aovs;
    aovs.rawDepth = cpu::splatDepth(s.camera, positions, s.radiusM);
    switch (s.view) {
        case View::Depth: aovs.color = depthView(aovs.rawDepth); break;
    }
    return aovs;
}

}  // namespace meniscus
