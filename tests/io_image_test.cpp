// Image writers (src/io/png_writer.cpp, src/io/exr_writer.cpp): round trips
// read back with libpng / OpenEXR directly, checking the sRGB encoding of
// PNGs exactly, float32 bit-identity of EXRs, row order (Image row 0 = first
// PNG row = EXR scanline at dataWindow.min.y), and that failures leave no
// file (final or temporary) behind.
#include <algorithm>
#include <bit>
#include <random>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>
#include <png.h>

#include "meniscus/io.h"
#include "shared/srgb.h"
#include "test_util.h"

namespace meniscus::io_image_test_local {
namespace {
namespace fs = std::filesystem;
using test::ExrData;
using test::PngData;
using test::readExr;
using test::readPng;

const float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();

// Reference sRGB encoding, written independently of the writer.
int srgb8(float linear) {
    double x = std::isnan(linear) ? 0.0 : std::min(1.0, std::max(0.0, double(linear)));
    double v = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return int(std::floor(v * 255.0 + 0.5));
}
int linear8(float a) {
    double x = std::isnan(a) ? 0.0 : std::min(1.0, std::max(0.0, double(a)));
    return int(std::floor(x * 255.0 + 0.5));
}

std::vector<std::string> listDir(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// 7x5 image, a distinct value in every channel of every pixel, plus the
// interesting values in the first pixels.
Image<glm::vec4> testImage() {
    Image<glm::vec4> im(7, 5);
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const float k = float(y * im.width + x);
            im.at(x, y) = glm::vec4(k / 40.0f, (k + 0.25f) / 41.0f, (34.0f - k) / 37.0f, (k + 0.5f) / 36.0f);
        }
    im.at(0, 0) = glm::vec4(0.0f, 1.0f, 0.5f, 1.0f);   // 0 -> 0, 1 -> 255, mid-grey -> 188
    im.at(1, 0) = glm::vec4(2.0f, -1.0f, 0.18f, 0.0f); // >1 clamps, <0 clamps
    im.at(2, 0) = glm::vec4(kNaN, 0.001f, 0.0031308f, kNaN);
    im.at(3, 0) = glm::vec4(0.01f, 0.214f, 0.9f, 3.0f);
    return im;
}

TEST(PngWriter, RgbaRoundTripMatchesSrgbFormula) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "rgba.png";
    const Image<glm::vec4> im = testImage();
    const Status st = writePng(file, im, true);
    ASSERT_TRUE(st.ok()) << st.error().describe();

    const PngData png = readPng(file);
    ASSERT_EQ(png.width, 7);
    ASSERT_EQ(png.height, 5);
    ASSERT_EQ(png.format, png_uint_32(PNG_FORMAT_RGBA));
    ASSERT_EQ(png.bytes.size(), std::size_t(7 * 5 * 4));
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const std::uint8_t* px = &png.bytes[std::size_t(y * 7 + x) * 4];  // PNG row y, first row first
            const glm::vec4& v = im.at(x, y);
            EXPECT_EQ(px[0], srgb8(v.r)) << x << "," << y;
            EXPECT_EQ(px[1], srgb8(v.g)) << x << "," << y;
            EXPECT_EQ(px[2], srgb8(v.b)) << x << "," << y;
            EXPECT_EQ(px[3], linear8(v.a)) << x << "," << y;
        }

    // Known values, independent of the reference function.
    const std::uint8_t* p0 = &png.bytes[0];
    EXPECT_EQ(p0[0], 0);
    EXPECT_EQ(p0[1], 255);
    EXPECT_EQ(p0[2], 188);  // linear 0.5
    EXPECT_EQ(p0[3], 255);
    const std::uint8_t* p1 = &png.bytes[4];
    EXPECT_EQ(p1[0], 255);  // 2.0 clamps
    EXPECT_EQ(p1[1], 0);    // -1 clamps
    EXPECT_EQ(p1[2], 118);  // linear 0.18
    EXPECT_EQ(p1[3], 0);
    const std::uint8_t* p2 = &png.bytes[8];
    EXPECT_EQ(p2[0], 0);   // NaN
    EXPECT_EQ(p2[1], 3);   // linear segment: 12.92 * 0.001 * 255 = 3.29
    EXPECT_EQ(p2[2], 10);  // at the knee
    EXPECT_EQ(p2[3], 0);   // NaN alpha
    const std::uint8_t* p3 = &png.bytes[12];
    EXPECT_EQ(p3[0], 25);
    EXPECT_EQ(p3[1], 127);
    EXPECT_EQ(p3[2], 243);
    EXPECT_EQ(p3[3], 255);  // alpha 3 clamps
    // Alpha is not sRGB-encoded: 0.5/36 linear -> 4, not the sRGB value.
    EXPECT_EQ(png.bytes[std::size_t(1 * 7 + 0) * 4 + 3], linear8((7.0f + 0.5f) / 36.0f));
}

TEST(PngWriter, RowZeroIsFirstPngRow) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "rows.png";
    Image<glm::vec4> im(3, 4, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    im.at(0, 0) = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);  // top-left red
    im.at(2, 3) = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);  // bottom-right blue
    ASSERT_TRUE(writePng(file, im).ok());
    const PngData png = readPng(file);
    ASSERT_EQ(png.bytes.size(), std::size_t(3 * 4 * 4));
    EXPECT_EQ(png.bytes[0], 255);  // first byte of the file's first row: red of pixel (0,0)
    EXPECT_EQ(png.bytes[2], 0);
    const std::size_t last = png.bytes.size() - 4;
    EXPECT_EQ(png.bytes[last + 0], 0);
    EXPECT_EQ(png.bytes[last + 2], 255);
}

TEST(PngWriter, RgbOnly) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "rgb.png";
    const Image<glm::vec4> im = testImage();
    ASSERT_TRUE(writePng(file, im, false).ok());
    const PngData png = readPng(file);
    ASSERT_EQ(png.format, png_uint_32(PNG_FORMAT_RGB));
    ASSERT_EQ(png.bytes.size(), std::size_t(7 * 5 * 3));
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const std::uint8_t* px = &png.bytes[std::size_t(y * 7 + x) * 3];
            EXPECT_EQ(px[0], srgb8(im.at(x, y).r)) << x << "," << y;
            EXPECT_EQ(px[1], srgb8(im.at(x, y).g)) << x << "," << y;
            EXPECT_EQ(px[2], srgb8(im.at(x, y).b)) << x << "," << y;
        }
}

TEST(PngWriter, CarriesSrgbChunk) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "srgb.png";
    ASSERT_TRUE(writePng(file, testImage()).ok());
    const PngData png = readPng(file);
    EXPECT_EQ(png.flags & PNG_IMAGE_FLAG_COLORSPACE_NOT_sRGB, 0u);
    const std::vector<std::uint8_t> bytes = test::readBytes(file);
    const std::string tag = "sRGB";
    EXPECT_NE(std::search(bytes.begin(), bytes.end(), tag.begin(), tag.end()), bytes.end());
}

TEST(PngWriter, EmptyImageFails) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "empty.png";
    const Status st = writePng(file, Image<glm::vec4>{});
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("empty.png"), std::string::npos);
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(PngWriter, SizeMismatchFails) {
    const fs::path dir = test::tempDir();
    Image<glm::vec4> im(4, 4);
    im.pixels.pop_back();
    const Status st = writePng(dir / "bad.png", im);
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("bad.png"), std::string::npos);
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(PngWriter, MissingDirectoryFails) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "no_such_dir" / "out.png";
    const Status st = writePng(file, testImage());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().file, file.string());
    EXPECT_NE(st.error().describe().find("out.png"), std::string::npos);
    EXPECT_FALSE(fs::exists(file));
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(PngWriter, FailedRenameLeavesNoTempFile) {
    // The target is an existing directory: the temp file gets written, the
    // rename fails, and the temp file must be gone afterwards.
    const fs::path dir = test::tempDir();
    fs::create_directories(dir / "target.png" / "inner");
    const Status st = writePng(dir / "target.png", testImage());
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("target.png"), std::string::npos);
    EXPECT_EQ(listDir(dir), std::vector<std::string>{"target.png"});
    EXPECT_TRUE(fs::is_directory(dir / "target.png"));
}

TEST(PngWriter, LibpngErrorBecomesErrorAndLeavesNothing) {
    // libpng refuses rows wider than its default user limit (1,000,000) with
    // png_error (a longjmp): that must come back as an Error, with the temp
    // file that was already opened removed.
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "wide.png";
    const Image<glm::vec4> im(1000001, 1, glm::vec4(0.5f));
    const Status st = writePng(file, im);
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().file, file.string());
    EXPECT_NE(st.error().message.find("PNG"), std::string::npos) << st.error().message;
    EXPECT_NE(st.error().message.find("width"), std::string::npos) << st.error().message;  // libpng's warning
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(PngWriter, OverwriteReplacesExistingFile) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "over.png";
    test::writeBytes(file, std::vector<std::uint8_t>(200000, 0xAB));  // big junk file
    Image<glm::vec4> im(2, 2, glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
    ASSERT_TRUE(writePng(file, im).ok());
    EXPECT_LT(fs::file_size(file), 1000u);
    const PngData png = readPng(file);
    ASSERT_EQ(png.bytes.size(), std::size_t(2 * 2 * 4));
    EXPECT_EQ(png.bytes[0], 188);
    EXPECT_EQ(listDir(dir), std::vector<std::string>{"over.png"});
}

// ------------------------------------------------------------------ EXR

bool bitEqual(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

Aovs testAovs(int w, int h) {
    Aovs a;
    a.color = Image<glm::vec4>(w, h);
    a.depth = Image<float>(w, h);
    a.rawDepth = Image<float>(w, h);
    a.normal = Image<glm::vec3>(w, h);
    a.thickness = Image<float>(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float k = float(y * w + x);
            a.color.at(x, y) = glm::vec4(k * 0.1f, k * 0.2f + 1.5f, -k * 0.3f, k / 100.0f + 0.001f);
            a.depth.at(x, y) = (x + y) % 3 == 0 ? kInf : 1.0f + k * 0.37f;
            a.rawDepth.at(x, y) = (x + y) % 4 == 0 ? kInf : 2.0f + k * 0.013f;
            a.normal.at(x, y) = (x % 2 == 0) ? glm::vec3(0.0f) : glm::vec3(0.6f, -0.8f, k * 1e-3f);
            a.thickness.at(x, y) = (y == 1) ? 0.0f : k * 1e-4f + 1e-7f;
        }
    a.depth.at(0, 0) = kInf;
    a.thickness.at(1, 0) = 123456.789f;
    return a;
}

TEST(ExrWriter, AovsRoundTripBitIdentical) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "aovs.exr";
    const int w = 6, h = 4;
    const Aovs a = testAovs(w, h);
    const Status st = writeExrAovs(file, a);
    ASSERT_TRUE(st.ok()) << st.error().describe();
    EXPECT_EQ(listDir(dir), std::vector<std::string>{"aovs.exr"});

    const ExrData exr = readExr(file);
    EXPECT_EQ(exr.width, w);
    EXPECT_EQ(exr.height, h);
    EXPECT_EQ(exr.minX, 0);
    EXPECT_EQ(exr.minY, 0);
    EXPECT_EQ(exr.compression, Imf::ZIP_COMPRESSION);
    EXPECT_EQ(exr.lineOrder, Imf::INCREASING_Y);

    const std::set<std::string> expected{"R", "G", "B", "A", "coverage", "Z", "Zraw", "N.X", "N.Y", "N.Z", "T"};
    ASSERT_EQ(exr.names.size(), expected.size());
    EXPECT_EQ(std::set<std::string>(exr.names.begin(), exr.names.end()), expected);

    auto source = [&](const std::string& name, int x, int y) -> float {
        if (name == "R") return a.color.at(x, y).r;
        if (name == "G") return a.color.at(x, y).g;
        if (name == "B") return a.color.at(x, y).b;
        if (name == "A") return a.color.at(x, y).a;
        if (name == "Z") return a.depth.at(x, y);
        if (name == "Zraw") return a.rawDepth.at(x, y);
        if (name == "coverage") return std::isfinite(a.rawDepth.at(x, y)) ? 1.0f : 0.0f;
        if (name == "N.X") return a.normal.at(x, y).x;
        if (name == "N.Y") return a.normal.at(x, y).y;
        if (name == "N.Z") return a.normal.at(x, y).z;
        return a.thickness.at(x, y);
    };
    for (std::size_t c = 0; c < exr.names.size(); ++c) {
        const std::string& name = exr.names[c];
        EXPECT_EQ(exr.channels[c].type, Imf::FLOAT) << name;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float got = exr.channels[c].values[std::size_t(y * w + x)];
                EXPECT_TRUE(bitEqual(got, source(name, x, y)))
                    << name << " at " << x << "," << y << ": " << got << " vs " << source(name, x, y);
            }
        // Image row 0 is the EXR's first scanline (dataWindow.min.y).
        for (int x = 0; x < w; ++x)
            EXPECT_TRUE(bitEqual(exr.firstScanline[c][std::size_t(x)], source(name, x, 0))) << name << " x=" << x;
    }

    // +inf survives unclamped.
    const auto zIt = std::find(exr.names.begin(), exr.names.end(), "Z");
    ASSERT_NE(zIt, exr.names.end());
    const float z00 = exr.channels[std::size_t(zIt - exr.names.begin())].values[0];
    EXPECT_TRUE(std::isinf(z00) && z00 > 0.0f);
}

TEST(ExrWriter, EmptyAovsAreOmitted) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "some.exr";
    Aovs a = testAovs(5, 3);
    a.color = {};
    a.normal = {};
    a.rawDepth = {};
    ASSERT_TRUE(writeExrAovs(file, a).ok());
    const ExrData exr = readExr(file);
    // coverage comes from Z when Zraw is absent
    EXPECT_EQ(std::set<std::string>(exr.names.begin(), exr.names.end()), (std::set<std::string>{"T", "Z", "coverage"}));
}

TEST(ExrWriter, AllAovsEmptyFails) {
    const fs::path dir = test::tempDir();
    const Status st = writeExrAovs(dir / "none.exr", Aovs{});
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("none.exr"), std::string::npos);
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(ExrWriter, WriteExrChannelsAsGiven) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "plain.exr";
    Image<float> a(3, 2), b(3, 2);
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        a.pixels[i] = float(i);
        b.pixels[i] = -float(i) - 0.5f;
    }
    ASSERT_TRUE(writeExr(file, {{"alpha.one", &a}, {"beta", &b}}).ok());
    const ExrData exr = readExr(file);
    ASSERT_EQ(exr.names, (std::vector<std::string>{"alpha.one", "beta"}));
    EXPECT_EQ(exr.channels[0].values, a.pixels);
    EXPECT_EQ(exr.channels[1].values, b.pixels);
}

TEST(ExrWriter, MismatchedSizesFailAndLeaveNothing) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "mismatch.exr";
    Image<float> a(4, 4, 1.0f), b(4, 3, 2.0f);
    const Status st = writeExr(file, {{"A", &a}, {"B", &b}});
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().file, file.string());
    EXPECT_TRUE(listDir(dir).empty());

    Aovs aovs = testAovs(4, 4);
    aovs.thickness = Image<float>(5, 4);
    const Status st2 = writeExrAovs(file, aovs);
    ASSERT_FALSE(st2.ok());
    EXPECT_NE(st2.error().describe().find("mismatch.exr"), std::string::npos);
    EXPECT_TRUE(listDir(dir).empty());

    Aovs bad = testAovs(4, 4);
    bad.normal.pixels.pop_back();  // size fields disagree with the pixel count
    EXPECT_FALSE(writeExrAovs(file, bad).ok());
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(ExrWriter, BadChannelListsFail) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "bad.exr";
    Image<float> a(2, 2, 1.0f), empty;
    EXPECT_FALSE(writeExr(file, {}).ok());
    EXPECT_FALSE(writeExr(file, {{"A", &a}, {"A", &a}}).ok());  // duplicate name
    EXPECT_FALSE(writeExr(file, {{"A", nullptr}}).ok());        // null image
    EXPECT_FALSE(writeExr(file, {{"A", &empty}}).ok());         // empty image
    EXPECT_FALSE(writeExr(file, {{"", &a}}).ok());              // no name
    const Status st = writeExr(file, {{"A", &a}, {"B", &empty}});
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("bad.exr"), std::string::npos);
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(ExrWriter, MissingDirectoryFails) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "missing" / "out.exr";
    const Status st = writeExrAovs(file, testAovs(3, 3));
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().file, file.string());
    EXPECT_NE(st.error().describe().find("out.exr"), std::string::npos);
    EXPECT_FALSE(fs::exists(file));
    EXPECT_TRUE(listDir(dir).empty());
}

TEST(ExrWriter, FailedRenameLeavesNoTempFile) {
    const fs::path dir = test::tempDir();
    fs::create_directories(dir / "target.exr" / "inner");
    const Status st = writeExrAovs(dir / "target.exr", testAovs(3, 3));
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().describe().find("target.exr"), std::string::npos);
    EXPECT_EQ(listDir(dir), std::vector<std::string>{"target.exr"});
}

TEST(ExrWriter, OverwriteReplacesExistingFile) {
    const fs::path dir = test::tempDir();
    const fs::path file = dir / "over.exr";
    ASSERT_TRUE(writeExrAovs(file, testAovs(64, 48)).ok());  // a bigger valid EXR first
    const auto bigSize = fs::file_size(file);
    Image<float> z(2, 2, 7.0f);
    ASSERT_TRUE(writeExr(file, {{"Z", &z}}).ok());
    EXPECT_LT(fs::file_size(file), bigSize);
    const ExrData exr = readExr(file);
    EXPECT_EQ(exr.width, 2);
    EXPECT_EQ(exr.height, 2);
    EXPECT_EQ(exr.names, std::vector<std::string>{"Z"});
    EXPECT_EQ(exr.channels[0].values, z.pixels);
    EXPECT_EQ(listDir(dir), std::vector<std::string>{"over.exr"});

    // And over a file that is not an EXR at all.
    test::writeBytes(file, std::vector<std::uint8_t>(300000, 0x5A));
    ASSERT_TRUE(writeExr(file, {{"Z", &z}}).ok());
    EXPECT_LT(fs::file_size(file), 300000u);
    EXPECT_EQ(readExr(file).channels[0].values, z.pixels);
}

}  // namespace
// encodeSrgb8's 8-bit sRGB (a table, png_writer.cpp) is the formula's,
// lround(srgbEncode(x) * 255), on every float within 300 steps of each
// level's edge, at both ends of every bucket of its table (a float's top 16
// bits), on 200,000 random values and on the specials.
TEST(Srgb8, TheTableGivesTheFormulasBytes) {
    const auto formula = [](float x) { return std::uint8_t(std::lround(shared::srgbEncode(x) * 255.0)); };
    std::vector<float> values = {0.0f, -0.0f, -1.0f, 1.0f, 2.0f, std::numeric_limits<float>::infinity(),
                                 -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                                 std::numeric_limits<float>::denorm_min(), 0.0031308f, 1.0f - 1e-7f};
    const std::uint32_t one = std::bit_cast<std::uint32_t>(1.0f);
    for (int k = 0; k < 255; ++k) {  // each level's edge, by bisection on the formula
        std::uint32_t lo = 0, hi = one;
        while (hi - lo > 1) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            (formula(std::bit_cast<float>(mid)) > k ? hi : lo) = mid;
        }
        for (std::uint32_t b = hi - std::min<std::uint32_t>(hi, 300); b <= std::min(hi + 300, one); ++b)
            values.push_back(std::bit_cast<float>(b));
    }
    for (std::uint32_t b = 0; b <= one; b += 1u << 16) {
        values.push_back(std::bit_cast<float>(b));
        if (b > 0) values.push_back(std::bit_cast<float>(b - 1));
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 200000; ++i) values.push_back(u(rng));
    Image<glm::vec4> linear(int(values.size()), 1);
    for (std::size_t i = 0; i < values.size(); ++i) linear.pixels[i] = glm::vec4(values[i], values[i], values[i], 1.0f);
    const Image<glm::u8vec4> out = encodeSrgb8(linear);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < values.size(); ++i)
        if (out.pixels[i].r != formula(values[i]) && ++wrong <= 5)
            ADD_FAILURE() << "linear " << values[i] << " (bits " << std::bit_cast<std::uint32_t>(values[i]) << "): "
                          << int(out.pixels[i].r) << ", the formula " << int(formula(values[i]));
    EXPECT_EQ(wrong, 0u) << "of " << values.size();
}

}  // namespace meniscus::io_image_test_local
