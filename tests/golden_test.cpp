// Golden images: the CLI renders the real SPlisHSPlasH frame 21 (small set) at
// 320x180 with every filter (water) and every material (default filter), and
// the result must match tests/golden/*.png. The goldens are rendered with
// `--backend cpu` (the reference), so a change to a CPU stage fails here even
// on a machine where the default backend is GL; the GL backend is then held
// to the same images within the parity tolerance.
// CPU tolerance: at most 0.5% of the pixels may differ by more than 3/255 in
// any channel, and the mean absolute difference must stay below 0.5/255 (room
// for another compiler's or libm's last-bit differences, not for a changed look).
// GL tolerance: the CPU/GL colour parity of tests/gl_backend_test.cpp, i.e. no
// channel more than 2/255 off and at most 0.1% of the pixels more than 1/255
// off, on top of the CPU bounds (measured on llvmpipe: at most 1/255 anywhere).
// After an intended change of the look, re-approve with scripts/approve_golden.sh
// and look at the new images before committing them.
#include <cstdio>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "test_util.h"

namespace meniscus::golden_test_local {
namespace {
namespace fs = std::filesystem;

// Every look that has a golden: the filters (file frame21_<filter>.png) and
// the materials other than the default water (frame21_material_<name>.png),
// the surface noise and foam (frame21_noise.png), the velocity whitening
// (frame21_whiten.png), the spray drops (frame21_spray.png) and the
// silhouette reduction over no background, where its alpha shows (frame21_silhouette.png),
// reduced resolution (frame21_fluid-scale-0.5.png) and two fluids, the frame
// split across the tank into water and lava (frame21_two_fluids.png, from
// tests/data/splishsplash/two_fluids/).
struct Look {
    std::string file;  // golden file name without .png
    std::string args;  // CLI arguments that select it
    std::string input = "splishsplash/partio/ParticleData_Fluid_21.bgeo";  // under tests/data
};
const Look kLooks[] = {
    {"frame21_none", "--filter none"},
    {"frame21_gaussian", "--filter gaussian"},
    {"frame21_bilateral", "--filter bilateral"},
    {"frame21_binomial", "--filter binomial"},
    {"frame21_curvature-flow", "--filter curvature-flow"},
    {"frame21_narrow-range", "--filter narrow-range"},
    {"frame21_narrow-range-1d", "--filter narrow-range --separable"},
    {"frame21_material_murky", "--material murky"},
    {"frame21_material_milk", "--material milk"},
    {"frame21_material_lava", "--material lava"},
    {"frame21_material_sand", "--material sand"},
    {"frame21_noise", "--noise"},
    {"frame21_whiten", "--whiten"},
    {"frame21_spray", "--spray --spray-streak 0.03"},
    {"frame21_silhouette", "--silhouette --background none"},
    {"frame21_fluid-scale-0.5", "--fluid-scale 0.5"},
    {"frame21_two_fluids", "--fluid-attribute phase --material water,lava",
     "splishsplash/two_fluids/ParticleData_Fluid_21_phase.bgeo"},
};

class Golden : public testing::TestWithParam<std::tuple<std::string, int>> {};

TEST_P(Golden, MatchesTheApprovedImage) {
    const auto& [backend, lookIndex] = GetParam();
    const Look& look = kLooks[lookIndex];
    const fs::path golden = fs::path(MENISCUS_GOLDEN_DIR) / (look.file + ".png");
    ASSERT_TRUE(fs::exists(golden)) << golden << " missing: run scripts/approve_golden.sh";
    const fs::path out = test::tempDir() / (backend + "_" + look.file + ".png");
    std::string log;
    const int rc = test::runCommand(
        test::cliPath() + " render '" + test::testData(look.input).string() +
            "' -o '" + out.string() + "' --width 320 --height 180 --backend " + backend + " " + look.args,
        &log);
    if (rc != 0 && backend == "gl" && log.find("GL backend unavailable") != std::string::npos)
        GTEST_SKIP() << "no GL context: " << log;
    ASSERT_EQ(rc, 0) << log;
    const test::PngData want = test::readPng(golden), got = test::readPng(out);
    ASSERT_EQ(got.width, want.width);
    ASSERT_EQ(got.height, want.height);
    ASSERT_EQ(got.bytes.size(), want.bytes.size());
    const std::size_t channels = got.bytes.size() / (std::size_t(got.width) * got.height);
    std::size_t off = 0, over1 = 0;
    int maxDiff = 0;
    double sum = 0.0;
    for (std::size_t p = 0; p < got.bytes.size(); p += channels) {
        int worst = 0;
        for (std::size_t c = 0; c < channels; ++c) {
            const int d = std::abs(int(got.bytes[p + c]) - int(want.bytes[p + c]));
            worst = std::max(worst, d);
            sum += d;
        }
        maxDiff = std::max(maxDiff, worst);
        if (worst > 3) ++off;
        if (worst > 1) ++over1;
    }
    const std::size_t pixels = std::size_t(got.width) * got.height;
    const double mean = sum / double(got.bytes.size());
    std::printf("%-4s %-26s pixels off by > 3/255: %zu of %zu, max diff %d, mean %.4f\n", backend.c_str(),
                look.file.c_str(), off, pixels, maxDiff, mean);
    EXPECT_LE(off, pixels / 200) << look.file << ": " << off << " pixels differ by more than 3/255";
    EXPECT_LT(mean, 0.5) << look.file;
    if (backend == "gl") {
        EXPECT_LE(maxDiff, 2) << look.file;
        EXPECT_LE(over1, pixels / 1000) << look.file;
    }
}

INSTANTIATE_TEST_SUITE_P(EveryLook, Golden,
                         testing::Combine(testing::Values("cpu", "gl"),
                                          testing::Range(0, int(std::size(kLooks)))),
                         [](const auto& info) {
                             std::string n = std::get<0>(info.param) + "_" + kLooks[std::get<1>(info.param)].file;
                             for (char& ch : n)
                                 if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                             return n;
                         });

}  // namespace
}  // namespace meniscus::golden_test_local
