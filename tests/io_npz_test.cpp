// numpy .npz particle files (src/io/npz.cpp, src/io/pickle.cpp): PySPH's
// output (pickled particle dicts) and plain arrays, against fixtures written
// by numpy.savez / savez_compressed and h5py (tests/data/hdf5/README.txt,
// scripts/make_hdf5_fixtures.py).
#include <cmath>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "test_util.h"

namespace meniscus::io_npz_test_local {
namespace {

namespace fs = std::filesystem;
using test::testData;

fs::path data(const std::string& name) { return testData("hdf5/" + name); }

#define REQUIRE_NPZ()                                                                          \
    do {                                                                                       \
        if (!particleFormatAvailable(ParticleFormat::Npz)) GTEST_SKIP() << "built without libzip"; \
    } while (0)

const Attribute& attr(const ParticleSet& set, std::string_view name) {
    const Attribute* a = set.find(name);
    if (!a) ADD_FAILURE() << "no attribute " << name;
    static const Attribute none;
    return a ? *a : none;
}

void expectError(const Result<ParticleSet>& r, const std::string& file, const std::string& what) {
    ASSERT_FALSE(r.ok()) << "expected an error for " << file;
    EXPECT_EQ(r.error().file, file);
    EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().describe();
}

// Two particle sets hold the same positions and attributes, bit for bit.
void expectSameSet(const ParticleSet& a, const ParticleSet& b) {
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.size() * sizeof(glm::vec3)), 0);
    ASSERT_EQ(a.attributes.size(), b.attributes.size());
    for (const Attribute& x : a.attributes) {
        const Attribute* y = b.find(x.name);
        ASSERT_NE(y, nullptr) << x.name;
        EXPECT_EQ(x.type, y->type) << x.name;
        EXPECT_EQ(x.components, y->components) << x.name;
        EXPECT_EQ(x.ints, y->ints) << x.name;
        ASSERT_EQ(x.floats.size(), y->floats.size()) << x.name;
        if (!x.floats.empty()) {  // memcmp of an empty vector's null data is undefined
            EXPECT_EQ(std::memcmp(x.floats.data(), y->floats.data(), x.floats.size() * sizeof(float)), 0) << x.name;
        }
    }
}

// ---------------------------------------------------------------- PySPH's npz

TEST(PySphNpz, HoldsWhatItsHdf5Holds) {
    REQUIRE_NPZ();
    for (const char* npz : {"pysph_dam_break_2d_100.npz", "pysph_dam_break_2d_100_compressed.npz"}) {
        auto set = readParticles(data(npz));
        ASSERT_TRUE(set.ok()) << set.error().describe();
        EXPECT_TRUE(set->warnings.empty());
        ASSERT_EQ(set->size(), 120u) << npz;  // the "fluid" array
        EXPECT_EQ(set->positions[119], glm::vec3(float(0.1 + 0.02 * 11), float(0.1 + 0.02 * 9), 0.0f));
        EXPECT_EQ(attr(*set, kAttrVelocity).components, 3);
        EXPECT_EQ(attr(*set, kAttrDensity).floats[8], float(1000.0 + 8 * 0.25));
        EXPECT_EQ(attr(*set, "h").floats[0], float(1.3 * 0.02));
        EXPECT_EQ(attr(*set, "gid").ints[119], 119);
        EXPECT_EQ(attr(*set, "gradv").components, 4);
        if (particleFormatAvailable(ParticleFormat::Hdf5)) {
            // The same run written by HDFOutput: the same particles, bit for bit.
            for (const char* array : {"fluid", "boundary"}) {
                auto a = readParticles(data(npz) / array);
                auto b = readParticles(data("pysph_dam_break_2d_100.hdf5") / array);
                ASSERT_TRUE(a.ok()) << a.error().describe();
                ASSERT_TRUE(b.ok()) << b.error().describe();
                expectSameSet(*a, *b);
            }
        }
    }
    auto arrays = listParticleArrays(data("pysph_dam_break_2d_100.npz"));
    ASSERT_TRUE(arrays.ok()) << arrays.error().describe();
    ASSERT_EQ(arrays->size(), 2u);
    EXPECT_EQ((*arrays)[0].name, "fluid");  // the dict's own order
    EXPECT_EQ((*arrays)[0].count, 120u);
    EXPECT_EQ((*arrays)[1].name, "boundary");
    EXPECT_EQ((*arrays)[1].count, 60u);
    const fs::path missing = data("pysph_dam_break_2d_100.npz") / "water";
    expectError(readParticles(missing), missing.string(), "no particle array 'water'");
    EXPECT_EQ(frameNumberOf(data("pysph_dam_break_2d_100.npz") / "boundary"), 100);
}

// ---------------------------------------------------------------- plain arrays

TEST(Npz, PlainArrays) {
    REQUIRE_NPZ();
    auto set = readParticles(data("plain_arrays.npz"));
    ASSERT_TRUE(set.ok()) << set.error().describe();
    ASSERT_EQ(set->size(), 50u);
    // y was float32 in the file: the very values; rho big-endian float64.
    const Attribute& rho = attr(*set, kAttrDensity);
    EXPECT_EQ(rho.floats.front(), 900.0f);
    EXPECT_EQ(rho.floats.back(), 1100.0f);
    const Attribute& v = attr(*set, kAttrVelocity);
    EXPECT_EQ(v.floats[0], 1.5f);
    EXPECT_EQ(v.floats[2], -0.5f);
    const Attribute& id = attr(*set, kAttrId);
    ASSERT_EQ(id.type, AttributeType::Int);
    EXPECT_EQ(id.ints[49], 147);
    EXPECT_EQ(attr(*set, "count").type, AttributeType::Int);  // uint32
    EXPECT_EQ(attr(*set, "count").ints[49], 49);
    EXPECT_EQ(attr(*set, "wet").ints[0], 1);  // bool
    EXPECT_EQ(attr(*set, "wet").ints[1], 0);
    EXPECT_EQ(attr(*set, "h").floats[0], float(0.026));
    // A 0-d string array is not per-particle data: skipped, with a note.
    ASSERT_EQ(set->warnings.size(), 1u);
    EXPECT_NE(set->warnings[0].find("'note.npy' skipped"), std::string::npos) << set->warnings[0];
}

TEST(Npz, BodiesAndWholeVectors) {
    REQUIRE_NPZ();
    const fs::path file = data("plain_bodies_compressed.npz");
    auto fluid = readParticles(file);  // no top-level arrays: "fluid"
    ASSERT_TRUE(fluid.ok()) << fluid.error().describe();
    ASSERT_EQ(fluid->size(), 20u);
    // velocity (20, 3) in Fortran order: (0, -1, 0.25) for every particle.
    const Attribute& v = attr(*fluid, kAttrVelocity);
    ASSERT_EQ(v.components, 3);
    for (std::size_t k = 0; k < 20; ++k) {
        EXPECT_EQ(v.floats[3 * k], 0.0f);
        EXPECT_EQ(v.floats[3 * k + 1], -1.0f);
        EXPECT_EQ(v.floats[3 * k + 2], 0.25f);
    }
    EXPECT_EQ(attr(*fluid, kAttrId).ints[19], 19);
    auto wall = readParticles(file / "wall");  // positions from one (10, 3) array
    ASSERT_TRUE(wall.ok()) << wall.error().describe();
    ASSERT_EQ(wall->size(), 10u);
    EXPECT_EQ(wall->positions[0], glm::vec3(-0.1f, 0.0f, 0.0f));
    EXPECT_EQ(wall->positions[9], glm::vec3(0.1f, 0.0f, 0.0f));
    expectError(readParticles(file / "air"), (file / "air").string(), "no arrays under 'air/'");
}

TEST(Npz, NpyVersionsAndByteOrders) {
    REQUIRE_NPZ();
    auto set = readParticles(data("npy_versions.npz"));
    ASSERT_TRUE(set.ok()) << set.error().describe();
    ASSERT_EQ(set->size(), 4u);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(set->positions[std::size_t(k)], glm::vec3(float(k), 1.0f, 0.0f));
    EXPECT_EQ(attr(*set, kAttrId).ints, (std::vector<std::int64_t>{7, -8, 9, 2147483647}));
}

// ---------------------------------------------------------------- errors

TEST(Npz, BadFilesAreErrorsNamingTheFile) {
    REQUIRE_NPZ();
    const fs::path lies = data("bad_npy_header_lies.npz");
    expectError(readParticles(lies), lies.string(), "'x.npy': the .npy header declares 1000000000000 elements");
    const fs::path truncated = data("bad_npy_truncated.npz");
    expectError(readParticles(truncated), truncated.string(), "declares 8 elements (64 bytes) but 40 bytes follow");
    // x as complex numbers: skipped, so there are no positions.
    const fs::path dtype = data("bad_npy_dtype.npz");
    auto r = readParticles(dtype);
    expectError(r, dtype.string(), "no position arrays");

    const fs::path dir = test::tempDir() / "npz_bad";
    fs::create_directories(dir);
    const fs::path notZip = dir / "not_zip.npz";
    test::writeText(notZip, "x,y,z\n1,2,3\n");
    expectError(readParticles(notZip), notZip.string(), "not a readable .npz (zip) archive");

    // Cut short anywhere, or damaged anywhere: an error naming the file, or
    // (damage in the values) a whole frame; never a crash.
    for (const char* name : {"pysph_dam_break_2d_100.npz", "pysph_dam_break_2d_100_compressed.npz",
                             "plain_bodies_compressed.npz"}) {
        const auto bytes = test::readBytes(data(name));
        for (std::size_t cut = 0; cut < bytes.size(); cut += bytes.size() / 37 + 1) {
            const std::vector<std::uint8_t> part(bytes.begin(), bytes.begin() + long(cut));
            auto t = parseParticles(part, "cut.npz", ParticleFormat::Npz);
            ASSERT_FALSE(t.ok()) << name << " cut at " << cut;
            EXPECT_EQ(t.error().file, "cut.npz");
        }
        for (std::size_t at = 0; at < bytes.size(); at += 61) {
            std::vector<std::uint8_t> damaged = bytes;
            damaged[at] ^= 0xff;
            auto d = parseParticles(damaged, "damaged.npz", ParticleFormat::Npz);
            if (!d) {
                EXPECT_EQ(d.error().file, "damaged.npz");
            }
        }
    }

    // A member whose recorded size is far beyond its compressed bytes (a
    // zip bomb's claim) is refused before anything that size is allocated.
    auto bytes = test::readBytes(data("plain_bodies_compressed.npz"));
    bool patched = false;
    for (std::size_t k = 0; k + 46 <= bytes.size(); ++k)
        if (bytes[k] == 'P' && bytes[k + 1] == 'K' && bytes[k + 2] == 1 && bytes[k + 3] == 2) {
            const std::uint32_t huge = 0xF0000000u;  // uncompressed size in the central directory
            std::memcpy(&bytes[k + 24], &huge, 4);
            patched = true;
        }
    ASSERT_TRUE(patched);
    auto bomb = parseParticles(bytes, "bomb.npz", ParticleFormat::Npz);
    ASSERT_FALSE(bomb.ok());
    EXPECT_EQ(bomb.error().file, "bomb.npz");
}

TEST(Npz, ARendererGetsRadiiFromPySphsSmoothingLength) {
    REQUIRE_NPZ();
    auto set = readParticles(data("pysph_dam_break_2d_100.npz"));
    ASSERT_TRUE(set.ok()) << set.error().describe();
    auto h = addRadiusFromSmoothingLength(*set, 1.2f);
    ASSERT_TRUE(h.ok());
    EXPECT_EQ(*h, "h");
    EXPECT_FLOAT_EQ(attr(*set, "radius").floats[0], float(1.3 * 0.02) / 2.4f);
}

}  // namespace
}  // namespace meniscus::io_npz_test_local
