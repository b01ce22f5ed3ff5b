// Golden images: the CLI renders the real SPlisHSPlasH frame 21 (small set) with
// every filter at 320x180 and the result must match tests/golden/*.png.
// Tolerance: at most 0.5% of the pixels may differ by more than 3/255 in any
// channel, and the mean absolute difference must stay below 0.5/255 (room for
// another compiler's or libm's last-bit differences, not for a changed look).
// After an intended change of the look, re-approve with scripts/approve_golden.sh
// and look at the new images before committing them.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "test_util.h"

namespace meniscus {
namespace {
namespace fs = std::filesystem;

class Golden : public testing::TestWithParam<std::string> {};

TEST_P(Golden, MatchesTheApprovedImage) {
    const std::string name = GetParam();
    const fs::path golden = fs::path(MENISCUS_GOLDEN_DIR) / ("frame21_" + name + ".png");
    ASSERT_TRUE(fs::exists(golden)) << golden << " missing: run scripts/approve_golden.sh";
    const fs::path out = test::tempDir() / (name + ".png");
    std::string log;
    const std::string args = name == "narrow-range-1d" ? "--filter narrow-range --separable" : "--filter " + name;
    ASSERT_EQ(test::runCommand(test::cliPath() + " render '" +
                                   test::testData("splishsplash/partio/ParticleData_Fluid_21.bgeo").string() +
                                   "' -o '" + out.string() + "' --width 320 --height 180 " + args,
                               &log),
              0)
        << log;
    const test::PngData want = test::readPng(golden), got = test::readPng(out);
    ASSERT_EQ(got.width, want.width);
    ASSERT_EQ(got.height, want.height);
    ASSERT_EQ(got.bytes.size(), want.bytes.size());
    const std::size_t channels = got.bytes.size() / (std::size_t(got.width) * got.height);
    std::size_t off = 0;
    double sum = 0.0;
    for (std::size_t p = 0; p < got.bytes.size(); p += channels) {
        int worst = 0;
        for (std::size_t c = 0; c < channels; ++c) {
            const int d = std::abs(int(got.bytes[p + c]) - int(want.bytes[p + c]));
            worst = std::max(worst, d);
            sum += d;
        }
        if (worst > 3) ++off;
    }
    const std::size_t pixels = std::size_t(got.width) * got.height;
    EXPECT_LE(off, pixels / 200) << name << ": " << off << " pixels differ by more than 3/255";
    EXPECT_LT(sum / double(got.bytes.size()), 0.5) << name;
}

INSTANTIATE_TEST_SUITE_P(AllFilters, Golden,
                         testing::Values("none", "gaussian", "bilateral", "binomial", "curvature-flow", "narrow-range",
                                         "narrow-range-1d"),
                         [](const auto& info) {
                             std::string n = info.param;
                             for (char& ch : n)
                                 if (ch == '-') ch = '_';
                             return n;
                         });

}  // namespace
}  // namespace meniscus
