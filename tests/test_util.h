// Small helpers shared by the tests: data paths, temp dirs, file bytes, gzip.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <initializer_list>
#include <vector>

#include <OpenEXR/ImfPixelType.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfLineOrder.h>
#include <gtest/gtest.h>
#include <png.h>

#include "meniscus/camera.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "shared/environment.h"

namespace meniscus::test {

std::filesystem::path testData(const std::string& rel);  // tests/data/REL
std::filesystem::path repoData(const std::string& rel);  // data/REL

// Frame 21 of the small real dam break (SPlisHSPlasH, tests/data/splishsplash/partio),
// read once per test binary.
const ParticleSet& smallFrame21();
// Default render settings for `set` at W x H: its estimated radius, the automatic camera.
RenderSettings autoFramedSettings(const ParticleSet& set, int width, int height);
// A fresh, empty directory unique to the calling test; removed by the next run.
std::filesystem::path tempDir();
// tempDir() / name, emptied, holding the small real frame as f.bgeo (tests/data/splishsplash).
std::filesystem::path dirWithFrame(const std::string& name);
// 'path' for a shell command line.
std::string shellQuote(const std::filesystem::path& p);
// The CLI with these arguments (runCommand of cliPath() + " " + args).
int runCli(const std::string& args, std::string* output = nullptr);

std::vector<std::uint8_t> readBytes(const std::filesystem::path& p);
void writeBytes(const std::filesystem::path& p, const std::vector<std::uint8_t>& bytes);
void writeText(const std::filesystem::path& p, const std::string& text);
std::vector<std::uint8_t> toBytes(const std::string& s);

// gzip-compress (for making .bgeo.gz-like test inputs).
std::vector<std::uint8_t> gzipBytes(const std::vector<std::uint8_t>& raw);

// An error whose message names `name` and holds one of `words` (any case):
// what every reader's malformed-input test checks.
::testing::AssertionResult errorNames(const Error& e, const std::string& name,
                                      std::initializer_list<std::string_view> words);
// !r.ok(), and its error as errorNames says.
template <class T>
::testing::AssertionResult failsNaming(const Result<T>& r, const std::string& name,
                                       std::initializer_list<std::string_view> words) {
    if (r.ok()) return ::testing::AssertionFailure() << "succeeded where an error naming " << name << " was expected";
    return errorNames(r.error(), name, words);
}
template <class T>
::testing::AssertionResult failsNaming(const Result<T>& r, const std::string& name, std::string_view word) {
    return failsNaming(r, name, {word});
}

// Runs a shell command; returns its exit status, captures stdout+stderr.
int runCommand(const std::string& cmd, std::string* output = nullptr);

// Path of the built CLI.
std::string cliPath();

// Writes DIR/small.json, a small dam break for the simulator's CLI and
// viewer tests: 9 x 14 x 5 particles of r = 1 cm (free faces 2r inside,
// walls r) in a 0.4 x 0.4 x 0.1 m tank, 0.1 s at 50 fps; returns its path.
std::filesystem::path writeSmallScene(const std::filesystem::path& dir);

// One row of tests/data/splishsplash/frame_stats.csv, by column name; ADD_FAILUREs
// and returns an empty map when there is no row for (dataset, frame).
std::map<std::string, std::string> frameStatsRow(const std::string& dataset, int frame);

// A frame_stats column as a number; NaN when the column is missing.
double statsNumber(const std::map<std::string, std::string>& row, const std::string& column);

// numpy-style median: middle element for odd n, mean of the two middle ones for even n.
double numpyMedian(std::vector<float> v);

// Count, bounds (1e-5) and density min/max/median (0.01) of `set` against a frame_stats row.
void expectMatchesStats(const ParticleSet& set, const std::map<std::string, std::string>& row);

// ---- Reading images back (libpng / OpenEXR directly) ----------------------

struct PngData {
    int width = 0, height = 0;
    png_uint_32 format = 0, flags = 0;
    std::vector<std::uint8_t> bytes;
};
// Reads a PNG with the simplified API in its own format (no conversion).
PngData readPng(const std::filesystem::path& p);

struct ExrChannelData {
    Imf::PixelType type;
    std::vector<float> values;
};

struct ExrData {
    int width = 0, height = 0;
    int minX = 0, minY = 0;
    Imf::Compression compression = Imf::NO_COMPRESSION;
    Imf::LineOrder lineOrder = Imf::DECREASING_Y;
    std::vector<std::string> names;  // header order
    std::vector<ExrChannelData> channels;
    std::vector<std::vector<float>> firstScanline;  // per channel, read alone
};
// Reads every channel as float, plus the first scanline on its own.
ExrData readExr(const std::filesystem::path& p);

// ---- Synthetic scenes for the pipeline tests ------------------------------

// nx*ny*nz particles on a grid of `spacing` starting at `origin` (x, y, z
// increasing), each moved by a uniform random offset in [-jitter, jitter]*spacing
// per axis (fixed seed: the same block every run).
std::vector<glm::vec3> jitteredBlock(glm::ivec3 n, float spacing, float jitter, glm::vec3 origin,
                                     unsigned seed = 1);

// Grid points at `spacing` inside a ball of radius `ballRadius` around `centre`.
std::vector<glm::vec3> ballOfParticles(glm::vec3 centre, float ballRadius, float spacing);

// A ball whose particles lie on concentric spherical shells (radii R, R - s,
// R - 2s, ...), each shell covered by a Fibonacci spiral at about `spacing`
// between neighbours: its outer surface is the sphere of radius R + r with
// only the small bumps between neighbouring particles (unlike a grid ball,
// whose surface is terraced).
std::vector<glm::vec3> shellBall(glm::vec3 centre, float ballRadius, float spacing);

// A camera at target + (0, 0, distance) looking down -z at `target`, up +y.
Camera faceOnCamera(glm::vec3 target, float distance, int width, int height, float fovYDegrees = 40.0f);

// A camera at `eye` looking at `target` (up +y, fov 40 degrees), w x h pixels.
Camera lookAt(glm::vec3 eye, glm::vec3 target, int w = 160, int h = 120);

// A cheap deterministic scramble of (i, salt) into [0, 1), for test images.
float hash01(std::uint32_t i, std::uint32_t salt);

// Pixels whose bits differ between a and b (a size mismatch counts every
// missing pixel).
template <class T>
int differingBits(const Image<T>& a, const Image<T>& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    int n = 0;
    for (std::size_t k = 0; k < a.size() && k < b.size(); ++k)
        n += std::memcmp(&a.pixels[k], &b.pixels[k], sizeof(T)) != 0;
    return n + int(a.size() > b.size() ? a.size() - b.size() : b.size() - a.size());
}

// An environment map of one radiance everywhere (width x height texels) with
// its irradiance: a constant map of radiance L lights a surface by L in every
// direction, so tests can tell its light from the studio's. It owns its
// texels (the map points into them), so it is neither copied nor moved.
struct ConstantEnvironment {
    explicit ConstantEnvironment(glm::vec3 radiance, int width = 16, int height = 8);
    ConstantEnvironment(const ConstantEnvironment&) = delete;
    ConstantEnvironment& operator=(const ConstantEnvironment&) = delete;
    std::vector<float> texels;
    shared::EnvironmentMap map;
};

}  // namespace meniscus::test
