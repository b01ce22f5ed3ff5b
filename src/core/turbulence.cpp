// TurbulenceTracker (turbulence.h).
#include "core/turbulence.h"

#include <algorithm>

namespace meniscus {

std::vector<float> TurbulenceTracker::update(std::span<const std::int64_t> ids, std::span<const glm::vec3> velocities) {
    const std::size_t n = std::min(ids.size(), velocities.size());
    const float tau2 = p_.tauMps * p_.tauMps;
    const int hold = std::max(p_.holdFrames, 1);
    const float boost = std::max(p_.boost, 1.0f);
    std::vector<float> factor(n, 1.0f);
    std::unordered_map<std::int64_t, State> next;
    next.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
        State s;
        s.velocity = velocities[k];
        if (auto it = state_.find(ids[k]); it != state_.end()) {
            const glm::vec3 dv = velocities[k] - it->second.velocity;
            // Turbulent now: the full boost for hold frames; else one frame
            // further into the fade of an earlier one.
            s.framesLeft = glm::dot(dv, dv) > tau2 ? hold : std::max(it->second.framesLeft - 1, 0);
        }
        factor[k] = 1.0f + (boost - 1.0f) * float(s.framesLeft) / float(hold);
        next[ids[k]] = s;
    }
    state_.swap(next);
    return factor;
}

}  // namespace meniscus
