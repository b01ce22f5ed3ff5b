// Radiance RGBE (.hdr) environment maps (src/io/radiance_hdr.cpp): pictures
// written here byte by byte, flat and in both run-length encodings, read back
// to the exact texels (m + 0.5) 2^(e - 136) / EXPOSURE; truncated, damaged and
// unsupported pictures give errors that name the file.
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/environment.h"
#include "test_util.h"

namespace io_environment_hdr_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

using Bytes = std::vector<std::uint8_t>;

struct Pixel {
    std::uint8_t r, g, b, e;
};

Bytes header(int w, int h, const std::string& extra = "") {
    const std::string s = "#?RADIANCE\n# written by the test\nFORMAT=32-bit_rle_rgbe\n" + extra + "\n-Y " +
                          std::to_string(h) + " +X " + std::to_string(w) + "\n";
    return Bytes(s.begin(), s.end());
}

void append(Bytes& b, std::initializer_list<int> v) {
    for (int x : v) b.push_back(std::uint8_t(x));
}

void appendFlat(Bytes& b, const std::vector<Pixel>& row) {
    for (const Pixel& p : row) append(b, {p.r, p.g, p.b, p.e});
}

// The adaptive run-length scanline of `row`: per component, runs of equal
// bytes of 3 or more as (128 + n, value), the rest as literal dumps.
void appendRle(Bytes& b, const std::vector<Pixel>& row) {
    const int w = int(row.size());
    append(b, {2, 2, w >> 8, w & 0xff});
    for (int c = 0; c < 4; ++c) {
        auto at = [&](int x) {
            const Pixel& p = row[std::size_t(x)];
            return c == 0 ? p.r : c == 1 ? p.g : c == 2 ? p.b : p.e;
        };
        int x = 0;
        while (x < w) {
            int run = 1;
            while (x + run < w && run < 127 && at(x + run) == at(x)) ++run;
            if (run >= 3) {
                append(b, {128 + run, at(x)});
                x += run;
                continue;
            }
            int n = 0;
            while (x + n < w && n < 128) {
                if (x + n + 2 < w && at(x + n) == at(x + n + 1) && at(x + n) == at(x + n + 2)) break;
                ++n;
            }
            b.push_back(std::uint8_t(n));
            for (int k = 0; k < n; ++k) b.push_back(at(x + k));
            x += n;
        }
    }
}

std::filesystem::path write(const std::filesystem::path& dir, const std::string& name, const Bytes& b) {
    const auto p = dir / name;
    std::ofstream out(p, std::ios::binary);
    out.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
    return p;
}

// Radiance's (m + 0.5) 2^(e - 136), 0 for e = 0.
float value(int m, int e) {
    return e == 0 ? 0.0f : std::ldexp(float(m) + 0.5f, e - 136);
}

// A w x h picture of varied pixels with runs in every component.
std::vector<std::vector<Pixel>> picture(int w, int h) {
    std::vector<std::vector<Pixel>> rows;
    for (int y = 0; y < h; ++y) {
        std::vector<Pixel> row;
        for (int x = 0; x < w; ++x) {
            const bool run = x >= 3 && x < 9;  // a run of 6 in every component
            row.push_back({std::uint8_t(run ? 200 : 17 * x + y), std::uint8_t(run ? 100 : 255 - 9 * x),
                           std::uint8_t(run ? 1 : 3 * x * y), std::uint8_t(run ? 130 : (x == 1 ? 0 : 120 + x + y))});
        }
        rows.push_back(row);
    }
    return rows;
}

void expectPicture(const EnvironmentImage& m, const std::vector<std::vector<Pixel>>& rows, double exposure = 1.0) {
    ASSERT_EQ(m.height, int(rows.size()));
    ASSERT_EQ(m.width, int(rows[0].size()));
    ASSERT_EQ(m.rgb.size(), std::size_t(m.width * m.height * 3));
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            const Pixel& p = rows[std::size_t(y)][std::size_t(x)];
            const float* t = &m.rgb[std::size_t(3 * (y * m.width + x))];
            EXPECT_EQ(t[0], float(value(p.r, p.e) / exposure)) << x << "," << y;
            EXPECT_EQ(t[1], float(value(p.g, p.e) / exposure)) << x << "," << y;
            EXPECT_EQ(t[2], float(value(p.b, p.e) / exposure)) << x << "," << y;
        }
}

}  // namespace

TEST(RadianceHdr, FlatScanlinesGiveTheExactTexels) {
    const auto dir = tempDir();
    Bytes b = header(3, 2);
    appendFlat(b, {{128, 64, 0, 129}, {255, 255, 255, 136}, {9, 9, 9, 0}});
    appendFlat(b, {{0, 0, 0, 1}, {1, 2, 3, 200}, {127, 0, 255, 128}});
    auto m = readEnvironmentMap(write(dir, "flat.hdr", b));
    ASSERT_TRUE(m.ok()) << m.error().describe();
    ASSERT_EQ(m->width, 3);
    ASSERT_EQ(m->height, 2);
    // The first pixel: (128.5, 64.5, 0.5) / 128.
    EXPECT_EQ(m->rgb[0], 1.00390625f);
    EXPECT_EQ(m->rgb[1], 0.50390625f);
    EXPECT_EQ(m->rgb[2], 0.00390625f);
    EXPECT_EQ(m->rgb[3], 255.5f);    // e = 136: (m + 0.5) 2^0
    EXPECT_EQ(m->rgb[6], 0.0f);      // e = 0: black whatever m says
    EXPECT_EQ(m->rgb[9 + 6 + 2], 255.5f / 256.0f);
    expectPicture(*m, {{{128, 64, 0, 129}, {255, 255, 255, 136}, {9, 9, 9, 0}},
                       {{0, 0, 0, 1}, {1, 2, 3, 200}, {127, 0, 255, 128}}});
}

TEST(RadianceHdr, RunLengthScanlinesGiveWhatFlatOnesGive) {
    const auto dir = tempDir();
    const auto rows = picture(20, 3);
    Bytes flat = header(20, 3), rle = header(20, 3);
    for (const auto& row : rows) {
        appendFlat(flat, row);
        appendRle(rle, row);
    }
    EXPECT_LT(rle.size(), flat.size());  // the runs were used
    auto a = readEnvironmentMap(write(dir, "flat.hdr", flat));
    auto r = readEnvironmentMap(write(dir, "rle.hdr", rle));
    ASSERT_TRUE(a.ok()) << a.error().describe();
    ASSERT_TRUE(r.ok()) << r.error().describe();
    expectPicture(*a, rows);
    expectPicture(*r, rows);
    // The two encodings may share one file, scanline by scanline.
    Bytes mixed = header(20, 3);
    appendRle(mixed, rows[0]);
    appendFlat(mixed, rows[1]);
    appendRle(mixed, rows[2]);
    auto x = readEnvironmentMap(write(dir, "mixed.hdr", mixed));
    ASSERT_TRUE(x.ok()) << x.error().describe();
    expectPicture(*x, rows);
}

TEST(RadianceHdr, OldStyleRepeatsCopyThePreviousPixel) {
    const auto dir = tempDir();
    // Width 300: 1 pixel, then repeat 43 + (1 << 8) = 299 times (two repeat
    // pixels in a row shift the second count by 8 bits).
    Bytes b = header(300, 2);
    append(b, {10, 20, 30, 140, 1, 1, 1, 43, 1, 1, 1, 1});
    // Second row: 2 pixels, repeat 3, then 295 flat pixels.
    append(b, {5, 6, 7, 130, 8, 9, 10, 131, 1, 1, 1, 3});
    for (int x = 0; x < 295; ++x) append(b, {x & 0xff, 1, 2, 128});
    auto m = readEnvironmentMap(write(dir, "old.hdr", b));
    ASSERT_TRUE(m.ok()) << m.error().describe();
    for (int x = 0; x < 300; ++x) {
        EXPECT_EQ(m->rgb[std::size_t(3 * x)], value(10, 140)) << x;
        EXPECT_EQ(m->rgb[std::size_t(3 * x + 2)], value(30, 140)) << x;
    }
    const float* row1 = &m->rgb[3 * 300];
    EXPECT_EQ(row1[0], value(5, 130));
    for (int x = 1; x < 5; ++x) EXPECT_EQ(row1[3 * x + 1], value(9, 131)) << x;
    EXPECT_EQ(row1[3 * 5], value(0, 128));
    EXPECT_EQ(row1[3 * 299], value(294 & 0xff, 128));
}

TEST(RadianceHdr, ExposureIsDividedOut) {
    const auto dir = tempDir();
    const auto rows = picture(9, 2);
    // Cumulative: the pixels were multiplied by 2 and then by 4.
    Bytes b = header(9, 2, "EXPOSURE=2\nEXPOSURE=4.0\n");
    for (const auto& row : rows) appendRle(b, row);
    auto m = readEnvironmentMap(write(dir, "exposed.hdr", b));
    ASSERT_TRUE(m.ok()) << m.error().describe();
    expectPicture(*m, rows, 8.0);
    // An RGBE header may name itself #?RGBE and leave FORMAT out.
    const std::string s = "#?RGBE\n\n-Y 1 +X 1\n";
    Bytes bare(s.begin(), s.end());
    append(bare, {64, 64, 64, 137});
    auto one = readEnvironmentMap(write(dir, "bare.HDR", bare));
    ASSERT_TRUE(one.ok()) << one.error().describe();
    EXPECT_EQ(one->rgb[0], 129.0f);
}

TEST(RadianceHdr, DamagedPicturesAreErrorsThatNameTheFile) {
    const auto dir = tempDir();
    const auto rows = picture(20, 3);
    Bytes rle = header(20, 3);
    for (const auto& row : rows) appendRle(rle, row);
    auto expectError = [&](const std::string& name, const Bytes& b, const std::string& says) {
        auto m = readEnvironmentMap(write(dir, name, b));
        ASSERT_FALSE(m.ok()) << name;
        EXPECT_NE(m.error().describe().find(name), std::string::npos) << m.error().describe();
        EXPECT_NE(m.error().message.find(says), std::string::npos) << m.error().describe();
    };
    // Cut anywhere in the pixels: an error, never zeros in the missing place.
    const std::size_t start = header(20, 3).size();
    for (std::size_t cut = start; cut < rle.size(); cut += 7)
        expectError("cut.hdr", Bytes(rle.begin(), rle.begin() + std::ptrdiff_t(cut)), "end early");
    Bytes flat = header(3, 2);
    appendFlat(flat, {{1, 2, 3, 130}, {1, 2, 3, 130}, {1, 2, 3, 130}, {1, 2, 3, 130}, {1, 2, 3, 130}});
    expectError("short.hdr", flat, "end early");
    // A run past its scanline's end, a zero-length dump, a wrong scanline length.
    Bytes over = header(8, 1);
    append(over, {2, 2, 0, 8, 128 + 9, 1});
    expectError("over.hdr", over, "past the end");
    Bytes zero = header(8, 1);
    append(zero, {2, 2, 0, 8, 0});
    expectError("zero.hdr", zero, "past the end");
    Bytes length = header(8, 1);
    append(length, {2, 2, 0, 9});
    expectError("length.hdr", length, "wrong length");
    Bytes repeat = header(4, 1);
    append(repeat, {1, 1, 1, 2});
    expectError("repeat.hdr", repeat, "no pixel before");
    Bytes longRepeat = header(4, 1);
    append(longRepeat, {9, 9, 9, 130, 1, 1, 1, 4});
    expectError("longrepeat.hdr", longRepeat, "past the end");
    // The header.
    const std::string notHdr = "P6\n1 1\n255\n";
    expectError("magic.hdr", Bytes(notHdr.begin(), notHdr.end()), "#?RADIANCE");
    const std::string open = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n";
    expectError("open.hdr", Bytes(open.begin(), open.end()), "no end");
    const std::string xyz = "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\1\1\1\1";
    expectError("xyz.hdr", Bytes(xyz.begin(), xyz.end()), "XYZ");
    const std::string flipped = "#?RADIANCE\n\n+Y 1 +X 1\n\1\1\1\1";
    expectError("flipped.hdr", Bytes(flipped.begin(), flipped.end()), "orientation");
    const std::string rotated = "#?RADIANCE\n\n-X 1 +Y 1\n\1\1\1\1";
    expectError("rotated.hdr", Bytes(rotated.begin(), rotated.end()), "orientation");
    const std::string huge = "#?RADIANCE\n\n-Y 8192 +X 99999\n";
    expectError("huge.hdr", Bytes(huge.begin(), huge.end()), "limit");
    const std::string empty = "#?RADIANCE\n\n-Y 0 +X 4\n";
    expectError("empty.hdr", Bytes(empty.begin(), empty.end()), "positive");
    const std::string exposure = "#?RADIANCE\nEXPOSURE=-1\n\n-Y 1 +X 1\n\1\1\1\1";
    expectError("exposure.hdr", Bytes(exposure.begin(), exposure.end()), "EXPOSURE");
    expectError("nothing.hdr", Bytes{}, "#?RADIANCE");
}
}  // namespace io_environment_hdr_test_local
