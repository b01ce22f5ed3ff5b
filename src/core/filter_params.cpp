// Names and iteration counts of the smoothing filters, for the CLI and bench.
#include <array>
#include <string_view>
#include <type_traits>

#include "meniscus/params.h"

namespace meniscus {

namespace {

// Index i names the i-th alternative of FilterParams.
constexpr std::array<std::string_view, std::variant_size_v<FilterParams>> kNames = {
    "none", "gaussian", "bilateral", "binomial", "curvature-flow", "narrow-range"};

template <std::size_t I = 0>
bool makeByIndex(std::size_t index, FilterParams* out) {
    if constexpr (I < std::variant_size_v<FilterParams>) {
        if (index == I) {
            *out = std::variant_alternative_t<I, FilterParams>{};
            return true;
        }
        return makeByIndex<I + 1>(index, out);
    }
    return false;
}

}  // namespace

bool filterFromName(const std::string& name, FilterParams* out) {
    for (std::size_t i = 0; i < kNames.size(); ++i)
        if (kNames[i] == name) return makeByIndex(i, out);
    return false;
}

std::string filterName(const FilterParams& filter) { return std::string(kNames[filter.index()]); }

std::string filterNames() {
    std::string s;
    for (auto n : kNames) s += (s.empty() ? "" : ", ") + std::string(n);
    return s;
}

int filterIterations(const FilterParams& filter) {
    return std::visit(
        [](const auto& p) {
            if constexpr (std::is_same_v<std::decay_t<decltype(p)>, NoFilter>) return 0;
            else return p.iterations;
        },
        filter);
}

void setFilterIterations(FilterParams& filter, int iterations) {
    std::visit(
        [&](auto& p) {
            if constexpr (!std::is_same_v<std::decay_t<decltype(p)>, NoFilter>) p.iterations = iterations;
        },
        filter);
}

}  // namespace meniscus
