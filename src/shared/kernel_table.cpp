// Weight tables of the separable filters and the thickness blur (see
// kernel_table.h), shared by the CPU and GL backends.
#include "shared/kernel_table.h"

#include <algorithm>
#include <cmath>

namespace meniscus::shared {

namespace {
int padFor(int maxRadius) { return maxRadius + 1 + kTapGroup - 1; }
}  // namespace

KernelTable::KernelTable(int maxRadius, std::vector<double> rows)
    : maxRadius_(maxRadius), half_(padFor(maxRadius)), stride_(2 * padFor(maxRadius) + 1) {
    const int nRows = maxRadius + 2;
    // Normalise each row in double, then store it (and the difference to the
    // next row, used by the blend) in float.
    rows_.assign(std::size_t(nRows) * stride_, 0.0f);
    for (int n = 0; n < nRows; ++n) {
        double sum = 0.0;
        for (int j = 0; j < stride_; ++j) sum += rows[std::size_t(n) * stride_ + j];
        for (int j = 0; j < stride_; ++j)
            rows_[std::size_t(n) * stride_ + j] = float(rows[std::size_t(n) * stride_ + j] / sum);
    }
    diffs_.assign(std::size_t(nRows) * stride_, 0.0f);
    for (int n = 0; n + 1 < nRows; ++n)
        for (int j = 0; j < stride_; ++j)
            diffs_[std::size_t(n) * stride_ + j] =
                rows_[std::size_t(n + 1) * stride_ + j] - rows_[std::size_t(n) * stride_ + j];
}

KernelTable KernelTable::gaussian(int maxRadius) {
    maxRadius = std::max(0, maxRadius);
    const int half = padFor(maxRadius), stride = 2 * half + 1;
    std::vector<double> rows(std::size_t(maxRadius + 2) * stride, 0.0);
    for (int n = 0; n <= maxRadius + 1; ++n) {
        double* row = rows.data() + std::size_t(n) * stride + half;
        row[0] = 1.0;
        const double sigma = n / 3.0;
        for (int k = 1; k <= n; ++k) row[k] = row[-k] = std::exp(-0.5 * k * k / (sigma * sigma));
    }
    return KernelTable(maxRadius, std::move(rows));
}

KernelTable KernelTable::binomial(int maxRadius) {
    maxRadius = std::max(0, maxRadius);
    const int half = padFor(maxRadius), stride = 2 * half + 1;
    std::vector<double> rows(std::size_t(maxRadius + 2) * stride, 0.0);
    // Pascal's triangle built halving at every step, so row 2n holds
    // C(2n, j) / 4^n directly (no overflow: C(66, 33) > 2^64).
    std::vector<double> pascal{1.0};
    for (int level = 1; level <= 2 * (maxRadius + 1); ++level) {
        std::vector<double> next(pascal.size() + 1, 0.0);
        for (std::size_t j = 0; j < pascal.size(); ++j) {
            next[j] += 0.5 * pascal[j];
            next[j + 1] += 0.5 * pascal[j];
        }
        pascal.swap(next);
        if (level % 2 == 0) {
            const int n = level / 2;
            double* row = rows.data() + std::size_t(n) * stride + half;
            for (int k = -n; k <= n; ++k) row[k] = pascal[std::size_t(n + k)];
        }
    }
    rows[std::size_t(half)] = 1.0;  // n = 0: the identity
    return KernelTable(maxRadius, std::move(rows));
}

}  // namespace meniscus::shared
