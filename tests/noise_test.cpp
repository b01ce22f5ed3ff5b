// The surface noise's gradient noise (src/shared/noise.h): Perlin's improved
// noise on a hashed lattice and its fractal sum. Properties that a wrong
// fade, gradient set or hash would break.
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

#include <gtest/gtest.h>

#include "shared/noise.h"

namespace noise_test_local {

using meniscus::shared::fractalNoise3;
using meniscus::shared::noise3;
using meniscus::shared::noiseHash3;

TEST(Noise, ZeroAtEveryLatticePoint) {
    for (int x = -3; x <= 3; ++x)
        for (int y = -3; y <= 3; ++y)
            for (int z : {0, 1, 77, 100000, -5})
                EXPECT_EQ(noise3(glm::vec3(float(x), float(y), float(z))), 0.0f) << x << " " << y << " " << z;
}

TEST(Noise, BoundedCenteredAndNotFlat) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-50.0f, 50.0f);
    double sum = 0.0, sum2 = 0.0, peak = 0.0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
        const float v = noise3({u(rng), u(rng), u(rng)});
        sum += v, sum2 += double(v) * v, peak = std::max(peak, double(std::abs(v)));
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    std::printf("noise3: mean %.4f, sd %.4f, max |n| %.4f\n", mean, sd, peak);
    EXPECT_LT(std::abs(mean), 0.01);
    EXPECT_GT(sd, 0.15);  // improved noise with the twelve edge gradients: about 0.2
    EXPECT_LT(sd, 0.35);
    EXPECT_LE(peak, 1.1);  // Perlin's bound for these gradients is about 1.04
    EXPECT_GT(peak, 0.6);
}

// C2 fade and a bounded gradient: a step of 1e-3 moves the value by at most
// a few thousandths, and the difference quotient changes smoothly.
TEST(Noise, ContinuousWithBoundedSlope) {
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(-20.0f, 20.0f);
    const float h = 1e-3f;
    double worst = 0.0;
    for (int k = 0; k < 20000; ++k) {
        const glm::vec3 p{u(rng), u(rng), u(rng)};
        for (int a = 0; a < 3; ++a) {
            glm::vec3 q = p;
            q[a] += h;
            worst = std::max(worst, double(std::abs(noise3(q) - noise3(p))) / h);
        }
    }
    std::printf("noise3: largest slope %.3f per unit\n", worst);
    EXPECT_LT(worst, 4.0);
    EXPECT_GT(worst, 0.5);
}

// The particle id is the third coordinate: slices one id apart are
// independent patterns (correlation near 0), a slice is a fixed pattern
// (the same values every call), and shifting (x, y) moves it without change.
TEST(Noise, IdSlicesAreIndependentAndRigid) {
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 200; ++j) {
            const float x = 0.173f * float(i), y = 0.119f * float(j);
            const float a = noise3({x, y, 41.0f}), b = noise3({x, y, 42.0f});
            sxy += double(a) * b, sxx += double(a) * a, syy += double(b) * b;
            EXPECT_EQ(a, noise3({x, y, 41.0f}));
        }
    const double corr = sxy / std::sqrt(sxx * syy);
    std::printf("noise3: correlation of neighbouring id slices %.4f\n", corr);
    EXPECT_LT(std::abs(corr), 0.1);
    // Integer shifts of the lattice: the pattern of (x + 3, y - 2) is another
    // part of the same slice, not the same values (no short period).
    int same = 0;
    for (int i = 0; i < 100; ++i) {
        const float x = 0.31f * float(i) + 0.5f, y = 0.27f * float(i) + 0.25f;
        same += noise3({x, y, 7.0f}) == noise3({x + 256.0f, y, 7.0f});
    }
    EXPECT_LT(same, 5) << "a period of 256, as a permutation table would have";
}

TEST(Noise, HashAvalanches) {
    // Flipping one input bit flips about half of the output word's bits, and
    // changes the four top bits (the gradient's choice) nearly always.
    std::mt19937 rng(13);
    double flipped = 0.0;
    int trials = 0, topChanged = 0;
    for (int k = 0; k < 2000; ++k) {
        const glm::uvec3 v{rng(), rng(), rng()};
        const std::uint32_t h = noiseHash3(v).x;
        for (int axis = 0; axis < 3; ++axis) {
            glm::uvec3 w = v;
            w[axis] ^= 1u << (rng() % 32u);
            const std::uint32_t g = noiseHash3(w).x;
            flipped += std::popcount(h ^ g);
            topChanged += (h >> 28u) != (g >> 28u);
            ++trials;
        }
    }
    const double mean = flipped / trials, top = double(topChanged) / trials;
    std::printf("pcg3d: %.2f of 32 output bits flip per input bit; the top four change in %.1f %%\n", mean, 100.0 * top);
    EXPECT_GT(mean, 12.0);
    EXPECT_LT(mean, 20.0);
    EXPECT_GT(top, 0.85);  // 15/16 for an ideal hash
}

TEST(Noise, FractalSumIsNormalisedAndHasFinerDetail) {
    const glm::vec3 p{3.3f, -1.7f, 12.0f};
    EXPECT_EQ(fractalNoise3(p, 1, 2.0f, 0.5f), noise3(p + glm::vec3(0.0f)));
    EXPECT_EQ(fractalNoise3(p, 0, 2.0f, 0.5f), 0.0f);
    // Four octaves: still within the bound, and finer: values a short lag
    // apart are less alike than in one octave (the higher octaves decorrelate
    // them).
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(-20.0f, 20.0f);
    auto lagCorrelation = [&](int octaves) {
        double sab = 0.0, saa = 0.0, sbb = 0.0;
        for (int k = 0; k < 20000; ++k) {
            const glm::vec3 q{u(rng), u(rng), u(rng)};
            const double a = fractalNoise3(q, octaves, 2.0f, 0.5f), b = fractalNoise3(q + glm::vec3(0.3f, 0, 0), octaves, 2.0f, 0.5f);
            sab += a * b, saa += a * a, sbb += b * b;
        }
        return sab / std::sqrt(saa * sbb);
    };
    const double c1 = lagCorrelation(1), c4 = lagCorrelation(4);
    std::printf("fractalNoise3: correlation at a lag of 0.3, one octave %.3f, four %.3f\n", c1, c4);
    EXPECT_LT(c4, c1 - 0.05);
    double peak = 0.0;
    for (int k = 0; k < 20000; ++k) peak = std::max(peak, double(std::abs(fractalNoise3({u(rng), u(rng), u(rng)}, 4, 2.0f, 0.5f))));
    EXPECT_LE(peak, 1.1);
}
}  // namespace noise_test_local
