#include "test_util.h"

#include "meniscus/io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <cstring>
#include <iterator>
#include <random>
#include <sstream>
#include <stdexcept>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <zlib.h>

namespace meniscus::test {

RenderSettings autoFramedSettings(const ParticleSet& set, int width, int height) {
    RenderSettings s;
    s.radiusM = estimateRadius(set.positions).radius;
    Camera base;
    base.width = width;
    base.height = height;
    s.camera = autoFrameCamera(set.positions, s.radiusM, base);
    return s;
}

const ParticleSet& smallFrame21() {
    static const ParticleSet set = [] {
        auto r = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
        EXPECT_TRUE(r) << r.error().describe();
        return r ? *r : ParticleSet{};
    }();
    return set;
}
namespace fs = std::filesystem;

fs::path testData(const std::string& rel) { return fs::path(MENISCUS_TEST_DATA) / rel; }
fs::path repoData(const std::string& rel) { return fs::path(MENISCUS_DATA_DIR) / rel; }

fs::path tempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "meniscus_test";
    for (char& c : name)
        if (c == '/') c = '_';
    fs::path dir = fs::temp_directory_path() / "meniscus_tests" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

fs::path dirWithFrame(const std::string& name) {
    const fs::path dir = tempDir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"), dir / "f.bgeo");
    return dir;
}

std::string shellQuote(const fs::path& p) { return "'" + p.string() + "'"; }

::testing::AssertionResult errorNames(const Error& e, const std::string& name,
                                      std::initializer_list<std::string_view> words) {
    const std::string msg = e.describe();
    if (msg.find(name) == std::string::npos) return ::testing::AssertionFailure() << "does not name " << name << ": " << msg;
    const auto lower = [](std::string_view v) {
        std::string out(v);
        for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
        return out;
    };
    for (std::string_view w : words)
        if (lower(msg).find(lower(w)) != std::string::npos) return ::testing::AssertionSuccess() << msg;
    return ::testing::AssertionFailure() << "none of the expected words in: " << msg;
}

int runCli(const std::string& args, std::string* output) { return runCommand(cliPath() + " " + args, output); }

std::vector<std::uint8_t> readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + p.string());
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& p, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(p, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void writeText(const fs::path& p, const std::string& text) { writeBytes(p, toBytes(text)); }

std::vector<std::uint8_t> toBytes(const std::string& s) { return {s.begin(), s.end()}; }

std::vector<std::uint8_t> gzipBytes(const std::vector<std::uint8_t>& raw) {
    z_stream zs{};
    if (deflateInit2(&zs, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw std::runtime_error("deflateInit2 failed");
    std::vector<std::uint8_t> out(deflateBound(&zs, uLong(raw.size())) + 64);
    zs.next_in = const_cast<Bytef*>(raw.data());
    zs.avail_in = uInt(raw.size());
    zs.next_out = out.data();
    zs.avail_out = uInt(out.size());
    const int rc = deflate(&zs, Z_FINISH);
    deflateEnd(&zs);
    if (rc != Z_STREAM_END) throw std::runtime_error("deflate failed");
    out.resize(zs.total_out);
    return out;
}

int runCommand(const std::string& cmd, std::string* output) {
    const std::string full = cmd + " 2>&1";
    FILE* pipe = ::popen(full.c_str(), "r");
    if (!pipe) return -1;
    std::array<char, 4096> buf{};
    std::string text;
    while (std::fgets(buf.data(), int(buf.size()), pipe)) text += buf.data();
    const int status = ::pclose(pipe);
    if (output) *output = text;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string cliPath() { return MENISCUS_CLI; }

std::map<std::string, std::string> frameStatsRow(const std::string& dataset, int frame) {
    std::ifstream in(testData("splishsplash/frame_stats.csv"));
    auto split = [](const std::string& s) {
        std::vector<std::string> out;
        std::stringstream ss(s);
        std::string cell;
        while (std::getline(ss, cell, ',')) out.push_back(cell);
        return out;
    };
    std::string lineText;
    std::getline(in, lineText);
    const auto header = split(lineText);
    while (std::getline(in, lineText)) {
        const auto cells = split(lineText);
        if (cells.size() == header.size() && cells[0] == dataset && std::stoi(cells[1]) == frame) {
            std::map<std::string, std::string> row;
            for (std::size_t i = 0; i < cells.size(); ++i) row[header[i]] = cells[i];
            return row;
        }
    }
    ADD_FAILURE() << "no frame_stats row for " << dataset << " frame " << frame;
    return {};
}

double statsNumber(const std::map<std::string, std::string>& row, const std::string& column) {
    const auto it = row.find(column);
    return it == row.end() ? std::nan("") : std::stod(it->second);
}

double numpyMedian(std::vector<float> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? double(v[n / 2]) : 0.5 * (double(v[n / 2 - 1]) + double(v[n / 2]));
}

void expectMatchesStats(const ParticleSet& set, const std::map<std::string, std::string>& row) {
    ASSERT_EQ(set.size(), std::size_t(statsNumber(row, "num_particles")));
    Bounds b;
    for (const auto& p : set.positions) b.extend(p);
    EXPECT_NEAR(b.min.x, statsNumber(row, "xmin"), 1e-5);
    EXPECT_NEAR(b.min.y, statsNumber(row, "ymin"), 1e-5);
    EXPECT_NEAR(b.min.z, statsNumber(row, "zmin"), 1e-5);
    EXPECT_NEAR(b.max.x, statsNumber(row, "xmax"), 1e-5);
    EXPECT_NEAR(b.max.y, statsNumber(row, "ymax"), 1e-5);
    EXPECT_NEAR(b.max.z, statsNumber(row, "zmax"), 1e-5);
    const Attribute* rho = set.find(kAttrDensity);
    ASSERT_NE(rho, nullptr);
    ASSERT_EQ(rho->count(), set.size());
    EXPECT_NEAR(*std::min_element(rho->floats.begin(), rho->floats.end()), statsNumber(row, "density_min"), 0.01);
    EXPECT_NEAR(*std::max_element(rho->floats.begin(), rho->floats.end()), statsNumber(row, "density_max"), 0.01);
    EXPECT_NEAR(numpyMedian(rho->floats), statsNumber(row, "density_median"), 0.01);
}

// Reads a PNG with the simplified API in its own format (no conversion).
PngData readPng(const std::filesystem::path& p) {
    png_image image;
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    PngData out;
    if (!png_image_begin_read_from_file(&image, p.c_str())) {
        ADD_FAILURE() << "cannot read PNG " << p << ": " << image.message;
        return out;
    }
    out.width = int(image.width);
    out.height = int(image.height);
    out.format = image.format;
    out.flags = image.flags;
    out.bytes.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, out.bytes.data(), 0, nullptr)) {
        ADD_FAILURE() << "cannot decode PNG " << p << ": " << image.message;
        png_image_free(&image);
    }
    return out;
}

ExrData readExr(const std::filesystem::path& p) {
    ExrData out;
    Imf::InputFile file(p.c_str());
    const Imf::Header& h = file.header();
    const Imath::Box2i dw = h.dataWindow();
    out.minX = dw.min.x;
    out.minY = dw.min.y;
    out.width = dw.max.x - dw.min.x + 1;
    out.height = dw.max.y - dw.min.y + 1;
    out.compression = h.compression();
    out.lineOrder = h.lineOrder();
    Imf::FrameBuffer fb;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
        out.names.push_back(it.name());
        out.channels.push_back({it.channel().type, std::vector<float>(std::size_t(out.width) * out.height)});
    }
    for (std::size_t i = 0; i < out.names.size(); ++i) {
        char* base = reinterpret_cast<char*>(out.channels[i].values.data()) -
                     (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * out.width) * std::ptrdiff_t(sizeof(float));
        fb.insert(out.names[i], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * out.width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);

    // The first scanline on its own, into a one-row buffer.
    Imf::FrameBuffer rowFb;
    out.firstScanline.assign(out.names.size(), std::vector<float>(std::size_t(out.width)));
    for (std::size_t i = 0; i < out.names.size(); ++i) {
        char* base = reinterpret_cast<char*>(out.firstScanline[i].data()) -
                     (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * out.width) * std::ptrdiff_t(sizeof(float));
        rowFb.insert(out.names[i], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * out.width));
    }
    file.setFrameBuffer(rowFb);
    file.readPixels(dw.min.y, dw.min.y);
    return out;
}

std::vector<glm::vec3> jitteredBlock(glm::ivec3 n, float spacing, float jitter, glm::vec3 origin, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-jitter * spacing, jitter * spacing);
    std::vector<glm::vec3> out;
    out.reserve(std::size_t(n.x) * n.y * n.z);
    for (int k = 0; k < n.z; ++k)
        for (int j = 0; j < n.y; ++j)
            for (int i = 0; i < n.x; ++i) {
                const glm::vec3 p = origin + spacing * glm::vec3(i, j, k);
                const float dx = u(rng), dy = u(rng), dz = u(rng);
                out.push_back(p + glm::vec3(dx, dy, dz));
            }
    return out;
}

std::vector<glm::vec3> ballOfParticles(glm::vec3 centre, float ballRadius, float spacing) {
    std::vector<glm::vec3> out;
    const int m = int(std::ceil(ballRadius / spacing));
    for (int k = -m; k <= m; ++k)
        for (int j = -m; j <= m; ++j)
            for (int i = -m; i <= m; ++i) {
                const glm::vec3 o = spacing * glm::vec3(i, j, k);
                if (glm::length(o) <= ballRadius) out.push_back(centre + o);
            }
    return out;
}

std::vector<glm::vec3> shellBall(glm::vec3 centre, float ballRadius, float spacing) {
    std::vector<glm::vec3> out;
    const double golden = M_PI * (3.0 - std::sqrt(5.0));  // golden angle
    for (float rho = ballRadius; rho > 0.5f * spacing; rho -= spacing) {
        // Hexagonal packing: each point covers (sqrt(3)/2) s^2 of the shell.
        const int n = std::max(1, int(std::lround(4.0 * M_PI * rho * rho / (0.8660254 * spacing * spacing))));
        for (int i = 0; i < n; ++i) {
            const double y = 1.0 - 2.0 * (i + 0.5) / n;
            const double ring = std::sqrt(std::max(0.0, 1.0 - y * y));
            const double phi = golden * i;
            out.push_back(centre + rho * glm::vec3(float(ring * std::cos(phi)), float(y), float(ring * std::sin(phi))));
        }
    }
    out.push_back(centre);
    return out;
}

Camera lookAt(glm::vec3 eye, glm::vec3 target, int w, int h) {
    Camera c;
    c.eye = eye;
    c.target = target;
    c.width = w;
    c.height = h;
    c.fovYDegrees = 40.0f;
    return c;
}

Camera faceOnCamera(glm::vec3 target, float distance, int width, int height, float fovYDegrees) {
    Camera c;
    c.target = target;
    c.eye = target + glm::vec3(0.0f, 0.0f, distance);
    c.up = glm::vec3(0.0f, 1.0f, 0.0f);
    c.fovYDegrees = fovYDegrees;
    c.nearM = 0.01f * distance;
    c.farM = 100.0f * distance;
    c.width = width;
    c.height = height;
    return c;
}

std::filesystem::path writeSmallScene(const std::filesystem::path& dir) {
    const std::filesystem::path p = dir / "small.json";
    std::ofstream(p) << R"({
  "version": 1, "name": "small", "duration": 0.1, "fps": 50,
  "params": { "radius": 0.01 },
  "domain": { "min": [0, 0, 0], "max": [0.4, 0.4, 0.1] },
  "fluid": [ { "box": { "min": [0, 0, 0], "max": [0.2, 0.3, 0.1] } } ]
})";
    return p;
}

float hash01(std::uint32_t i, std::uint32_t salt) {
    std::uint32_t h = i * 2654435761u ^ (salt * 2246822519u + 0x9e3779b9u);
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    return float(h % 100000u) / 100000.0f;
}

ConstantEnvironment::ConstantEnvironment(glm::vec3 radiance, int width, int height) {
    for (int k = 0; k < width * height; ++k) texels.insert(texels.end(), {radiance.x, radiance.y, radiance.z});
    map.texels = texels.data();
    map.width = width;
    map.height = height;
    shared::environmentIrradianceSh(texels.data(), width, height, 0.0f, 1.0f, map.irradiance);
}

}  // namespace meniscus::test
