// Which particles of a sequence are turbulent
// (docs/pipeline.md#noise-and-foam): the surface noise of a particle whose
// velocity jumped between frames is drawn rougher for a while. The renderer
// keeps one tracker per sequence and feeds it each frame's ids and velocities;
// particles are matched by id, so the order of the particles in the files does
// not matter.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/params.h"

namespace meniscus {

class TurbulenceTracker {
public:
    explicit TurbulenceTracker(const TurbulenceParams& params = {}) : p_(params) {}

    // The next frame of the sequence: ids[k] and velocities[k] (m/s) of its
    // particles (the same length). Returns each particle's amplitude factor,
    // in [1, boost]: boost where |v - v_previous| > tau, then fading linearly
    // to 1 over holdFrames frames; 1 for a particle not in the previous frame
    // (new, or the first frame). Particles absent from this frame are
    // forgotten (memory stays proportional to one frame). An id repeated
    // within a frame is matched once: its last occurrence is remembered.
    std::vector<float> update(std::span<const std::int64_t> ids, std::span<const glm::vec3> velocities);

    // Forgets everything (a new sequence, or a jump in time).
    void reset() { state_.clear(); }

    std::size_t tracked() const { return state_.size(); }
    const TurbulenceParams& params() const { return p_; }

private:
    struct State {
        glm::vec3 velocity{0.0f};
        int framesLeft = 0;  // of the boost's fade; 0 = calm
    };
    TurbulenceParams p_;
    std::unordered_map<std::int64_t, State> state_;
};

}  // namespace meniscus
