// H5Part and PySPH .hdf5 files (src/io/h5part.cpp, src/io/pysph_hdf5.cpp,
// src/io/hdf5_util.cpp), paths into them (run.h5part/Step#3, out.hdf5/fluid)
// and sequences of them, against fixtures written by h5py
// (tests/data/hdf5/README.txt, scripts/make_hdf5_fixtures.py).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "meniscus/particle_view.h"
#include "meniscus/particles.h"
#include "test_util.h"

#if MENISCUS_TEST_HDF5
#include <hdf5.h>
#endif

namespace meniscus::io_hdf5_test_local {
namespace {

namespace fs = std::filesystem;
using test::testData;

fs::path data(const std::string& name) { return testData("hdf5/" + name); }

#define REQUIRE_HDF5()                                                                     \
    do {                                                                                   \
        if (!particleFormatAvailable(ParticleFormat::Hdf5)) GTEST_SKIP() << "built without HDF5"; \
    } while (0)

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

const Attribute& attr(const ParticleSet& set, std::string_view name) {
    const Attribute* a = set.find(name);
    if (!a) ADD_FAILURE() << "no attribute " << name;
    static const Attribute none;
    return a ? *a : none;
}

std::string joined(const std::vector<std::string>& v) {
    std::string out;
    for (const auto& s : v) out += s + "\n";
    return out;
}

// An error that names `file` (the path as given) and says `what`.
void expectError(const Result<ParticleSet>& r, const std::string& file, const std::string& what) {
    ASSERT_FALSE(r.ok()) << "expected an error for " << file;
    EXPECT_EQ(r.error().file, file);
    EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().describe();
}

// ---------------------------------------------------------------- H5Part

TEST(H5Part, RealFrameIsTheBgeoBitForBit) {
    REQUIRE_HDF5();
    auto h = readParticles(data("splishsplash_fluid21.h5part"));
    auto b = readParticles(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo"));
    ASSERT_TRUE(h.ok()) << h.error().describe();
    ASSERT_TRUE(b.ok()) << b.error().describe();
    EXPECT_TRUE(h->warnings.empty()) << joined(h->warnings);  // one step: no note
    ASSERT_EQ(h->size(), 6859u);
    ASSERT_EQ(h->size(), b->size());
    EXPECT_EQ(std::memcmp(h->positions.data(), b->positions.data(), h->size() * sizeof(glm::vec3)), 0);
    for (std::string_view name : {kAttrVelocity, kAttrDensity}) {
        const Attribute &x = attr(*h, name), &y = attr(*b, name);
        EXPECT_EQ(x.components, y.components) << name;
        ASSERT_EQ(x.floats.size(), y.floats.size()) << name;
        EXPECT_EQ(std::memcmp(x.floats.data(), y.floats.data(), x.floats.size() * sizeof(float)), 0) << name;
    }
    EXPECT_EQ(attr(*h, kAttrId).type, AttributeType::Int);
    EXPECT_EQ(attr(*h, kAttrId).ints, attr(*b, kAttrId).ints);
}

TEST(H5Part, StepsAreASequenceInStepOrder) {
    REQUIRE_HDF5();
    const fs::path file = data("steps.h5part");
    auto steps = listH5PartSteps(file);
    ASSERT_TRUE(steps.ok()) << steps.error().describe();
    EXPECT_EQ(*steps, (std::vector<std::string>{"Step#0", "Step#1", "Step#2", "Step#10"}));  // not name order
    EXPECT_TRUE(isSequenceSpec(file.string()));
    EXPECT_FALSE(isSequenceSpec(data("splishsplash_fluid21.h5part").string()));  // one step
    auto frames = expandSequence(file.string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    ASSERT_EQ(frames->size(), 4u);
    const long numbers[] = {0, 1, 2, 10};
    const std::size_t counts[] = {64, 80, 96, 100};
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ((*frames)[i], file / (*steps)[i]);
        EXPECT_EQ(frameNumberOf((*frames)[i]), numbers[i]);
        auto set = readParticles((*frames)[i]);
        ASSERT_TRUE(set.ok()) << set.error().describe();
        EXPECT_EQ(set->size(), counts[i]);
        EXPECT_TRUE(set->warnings.empty()) << joined(set->warnings);
    }
    // A single step given as the input is that one frame.
    auto one = expandSequence((file / "Step#2").string());
    ASSERT_TRUE(one.ok()) << one.error().describe();
    EXPECT_EQ(*one, std::vector<fs::path>{file / "Step#2"});
    EXPECT_FALSE(isSequenceSpec((file / "Step#2").string()));
}

TEST(H5Part, ValuesAreExact) {
    REQUIRE_HDF5();
    auto set = readParticles(data("steps.h5part") / "Step#10");
    ASSERT_TRUE(set.ok()) << set.error().describe();
    ASSERT_EQ(set->size(), 100u);
    // float64 x, y, z become the float numpy rounds them to (xf, yf, zf).
    const Attribute &xf = attr(*set, "xf"), &yf = attr(*set, "yf"), &zf = attr(*set, "zf");
    ASSERT_EQ(xf.floats.size(), 100u);
    for (std::size_t k = 0; k < set->size(); ++k) {
        EXPECT_TRUE(sameBits(set->positions[k].x, xf.floats[k])) << k;
        EXPECT_TRUE(sameBits(set->positions[k].y, yf.floats[k])) << k;
        EXPECT_TRUE(sameBits(set->positions[k].z, zf.floats[k])) << k;
    }
    // vx vy vz -> velocity; rho -> density; id int64 beyond int32, exact.
    const Attribute& v = attr(*set, kAttrVelocity);
    ASSERT_EQ(v.components, 3);
    EXPECT_EQ(v.floats[0], 0.5f);
    EXPECT_EQ(v.floats[1], float(-9.81 * 0.01 * 10));
    EXPECT_EQ(v.floats[2], 0.0f);
    const Attribute& rho = attr(*set, kAttrDensity);
    EXPECT_EQ(rho.floats.front(), 990.0f);
    EXPECT_EQ(rho.floats.back(), 1010.0f);
    const Attribute& id = attr(*set, kAttrId);
    ASSERT_EQ(id.type, AttributeType::Int);
    for (std::size_t k = 0; k < set->size(); ++k) EXPECT_EQ(id.ints[k], 1'000'000'000'000 + std::int64_t(k));
    // Others by their names: h (the smoothing length), mass, an int flag.
    EXPECT_EQ(attr(*set, "h").floats[7], float(0.024));
    EXPECT_EQ(attr(*set, "mass").floats[7], 0.008f);
    EXPECT_EQ(attr(*set, "flag").type, AttributeType::Int);
    EXPECT_EQ(attr(*set, "flag").ints[5], 2);
    // h gives the radius: r = h / (2 hPerSpacing).
    auto h = addRadiusFromSmoothingLength(*set, 1.2f);
    ASSERT_TRUE(h.ok());
    EXPECT_EQ(*h, "h");
    EXPECT_FLOAT_EQ(attr(*set, "radius").floats[0], 0.024f / 2.4f);
}

TEST(H5Part, TheWholeFileReadsItsFirstStepAndSaysSo) {
    REQUIRE_HDF5();
    const fs::path file = data("steps.h5part");
    auto set = readParticles(file);
    ASSERT_TRUE(set.ok()) << set.error().describe();
    EXPECT_EQ(set->size(), 64u);
    ASSERT_EQ(set->warnings.size(), 1u);
    EXPECT_NE(set->warnings[0].find("4 steps, Step#0 .. Step#10"), std::string::npos) << set->warnings[0];
    // From memory (the core driver) the same.
    const auto bytes = test::readBytes(file);
    auto mem = parseParticles(bytes, "mem.h5part");
    ASSERT_TRUE(mem.ok()) << mem.error().describe();
    EXPECT_EQ(mem->positions, set->positions);
    // Found by content with no extension.
    auto sniffed = parseParticles(bytes, "no_extension");
    ASSERT_TRUE(sniffed.ok()) << sniffed.error().describe();
    EXPECT_EQ(sniffed->size(), 64u);
}

TEST(H5Part, ADirectoryOrPatternGivesTheStepsOfItsFiles) {
    REQUIRE_HDF5();
    const fs::path dir = test::tempDir() / "h5part_dir";
    fs::create_directories(dir);
    fs::copy_file(data("steps.h5part"), dir / "run.h5part");
    for (const std::string& spec : {dir.string(), (dir / "*.h5part").string()}) {
        auto frames = expandSequence(spec);
        ASSERT_TRUE(frames.ok()) << frames.error().describe();
        ASSERT_EQ(frames->size(), 4u) << spec;
        EXPECT_EQ(frames->back(), dir / "run.h5part" / "Step#10");
    }
}

TEST(H5Part, BadFilesAreErrorsNamingTheFile) {
    REQUIRE_HDF5();
    const fs::path dir = test::tempDir() / "h5part_bad";
    fs::create_directories(dir);

    const fs::path text = dir / "text.h5part";
    test::writeText(text, "x y z\n1 2 3\n");
    expectError(readParticles(text), text.string(), "not an HDF5 file");

    const fs::path empty = dir / "empty.h5";
    test::writeText(empty, "");
    expectError(readParticles(empty), empty.string(), "empty");

    const fs::path noSteps = data("bad_no_steps.h5part");
    expectError(readParticles(noSteps), noSteps.string(), "neither H5Part steps");

    const fs::path noX = data("bad_step_without_x.h5part");
    expectError(readParticles(noX), noX.string(), "Step#0: no position dataset x");

    const fs::path unequal = data("bad_unequal_lengths.h5part");
    expectError(readParticles(unequal), unequal.string(), "dataset 'z' has 9 values but 'x' has 10");

    // A string dataset beside x, y, z is skipped with a warning; x of strings is an error.
    const fs::path types = data("bad_types.h5part");
    auto step0 = readParticles(types / "Step#0");
    ASSERT_TRUE(step0.ok()) << step0.error().describe();
    EXPECT_EQ(step0->size(), 5u);
    ASSERT_EQ(step0->warnings.size(), 1u);
    EXPECT_NE(step0->warnings[0].find("'label' skipped"), std::string::npos) << step0->warnings[0];
    expectError(readParticles(types / "Step#1"), (types / "Step#1").string(), "no position dataset x");

    const fs::path missing = data("steps.h5part") / "Step#7";
    expectError(readParticles(missing), missing.string(), "no step 'Step#7' (it has 4 steps, Step#0 .. Step#10)");

    // Truncated: every cut is an error, never a crash or a partial set.
    const auto bytes = test::readBytes(data("steps.h5part"));
    for (std::size_t cut : {std::size_t(16), bytes.size() / 4, bytes.size() / 2, bytes.size() - 100}) {
        const fs::path t = dir / ("cut_" + std::to_string(cut) + ".h5part");
        test::writeBytes(t, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + long(cut)));
        for (const fs::path& p : {t, t / "Step#10"}) {
            auto r = readParticles(p);
            ASSERT_FALSE(r.ok()) << p << " read " << r->size() << " particles";
            EXPECT_EQ(r.error().file, p.string());
        }
    }
    // Damaged bytes anywhere: an error naming the file, or a whole frame.
    for (std::size_t at = 0; at < bytes.size(); at += 997) {
        std::vector<std::uint8_t> damaged = bytes;
        for (std::size_t k = at; k < std::min(at + 8, damaged.size()); ++k) damaged[k] ^= 0x5a;
        auto r = parseParticles(damaged, "damaged.h5part");
        if (!r) EXPECT_EQ(r.error().file, "damaged.h5part");
        else
            for (const Attribute& a : r->attributes) EXPECT_EQ(a.count(), r->size()) << a.name;
    }
}

// ---------------------------------------------------------------- PySPH .hdf5

TEST(PySphHdf5, TheFluidArrayByDefault) {
    REQUIRE_HDF5();
    const fs::path file = data("pysph_dam_break_2d_100.hdf5");
    auto set = readParticles(file);
    ASSERT_TRUE(set.ok()) << set.error().describe();
    EXPECT_TRUE(set->warnings.empty()) << joined(set->warnings);
    ASSERT_EQ(set->size(), 120u);  // 12 x 10, not the boundary's 60
    // x = 0.1 + 0.02 i, y = 0.1 + 0.02 j (float64 -> float); z not stored: its default 0.
    EXPECT_EQ(set->positions[0], glm::vec3(0.1f, 0.1f, 0.0f));
    EXPECT_EQ(set->positions[11], glm::vec3(float(0.1 + 0.02 * 1), float(0.1 + 0.02 * 1), 0.0f));
    EXPECT_EQ(set->positions[119], glm::vec3(float(0.1 + 0.02 * 11), float(0.1 + 0.02 * 9), 0.0f));
    // u, v stored, w not: the velocity is (u, v, 0).
    const Attribute& vel = attr(*set, kAttrVelocity);
    ASSERT_EQ(vel.components, 3);
    EXPECT_NEAR(vel.floats[3 * 5 + 0], 0.1 * std::sin(5.0), 1e-7);  // numpy's sin, not necessarily libm's bits
    EXPECT_NEAR(vel.floats[3 * 5 + 1], -0.2 * std::cos(5.0), 1e-7);
    EXPECT_EQ(vel.floats[3 * 5 + 2], 0.0f);
    EXPECT_EQ(attr(*set, kAttrDensity).floats[8], float(1000.0 + 8 * 0.25));
    EXPECT_EQ(attr(*set, "h").floats[0], float(1.3 * 0.02));  // hdx dx
    EXPECT_EQ(attr(*set, "m").floats[0], float(1000.0 * 0.02 * 0.02));
    EXPECT_EQ(attr(*set, "gid").type, AttributeType::Int);  // uint32
    EXPECT_EQ(attr(*set, "gid").ints[119], 119);
    EXPECT_EQ(attr(*set, "tag").type, AttributeType::Int);
    // gradv has stride 4: four components per particle.
    const Attribute& gradv = attr(*set, "gradv");
    EXPECT_EQ(gradv.components, 4);
    EXPECT_EQ(gradv.floats[4 * 2 + 3], float((4 * 2 + 3) * 0.5));
    // Unstored properties (cs, au, x0, ...) are not attributes.
    EXPECT_EQ(set->find("cs"), nullptr);
    EXPECT_EQ(set->find("z"), nullptr);
    // The radius from h: hdx dx / (2 K); with K = hdx, half the spacing.
    auto h = addRadiusFromSmoothingLength(*set, 1.3f);
    ASSERT_TRUE(h.ok());
    EXPECT_NEAR(attr(*set, "radius").floats[0], 0.01f, 1e-7f);
}

TEST(PySphHdf5, AnArrayChosenByItsPath) {
    REQUIRE_HDF5();
    const fs::path file = data("pysph_dam_break_2d_100.hdf5");
    for (const fs::path& p : {file / "boundary", file / "particles" / "boundary"}) {
        auto set = readParticles(p);
        ASSERT_TRUE(set.ok()) << set.error().describe();
        EXPECT_EQ(set->size(), 60u) << p;
        EXPECT_EQ(set->positions[1], glm::vec3(0.0f, float(-0.02), 0.0f));
        EXPECT_EQ(set->find(kAttrVelocity), nullptr);  // no u, v, w stored
        EXPECT_EQ(frameNumberOf(p), 100);              // the file's number
    }
    auto fluid = readParticles(file / "fluid");
    ASSERT_TRUE(fluid.ok());
    EXPECT_EQ(fluid->size(), 120u);
    expectError(readParticles(file / "solid"), (file / "solid").string(),
                "no particle array 'solid' (it has 'boundary', 'fluid')");
    // Without a "fluid": the first array with particles, and a note.
    const fs::path other = data("pysph_no_fluid.hdf5");
    auto set = readParticles(other);
    ASSERT_TRUE(set.ok()) << set.error().describe();
    EXPECT_EQ(set->size(), 60u);  // 'solid' before 'water'
    ASSERT_EQ(set->warnings.size(), 1u);
    EXPECT_NE(set->warnings[0].find("none named 'fluid': read 'solid'"), std::string::npos) << set->warnings[0];
    auto arrays = listParticleArrays(other);
    ASSERT_TRUE(arrays.ok()) << arrays.error().describe();
    ASSERT_EQ(arrays->size(), 2u);
    EXPECT_EQ((*arrays)[0].name, "solid");
    EXPECT_EQ((*arrays)[0].count, 60u);
    EXPECT_EQ((*arrays)[1].name, "water");
    EXPECT_EQ((*arrays)[1].count, 120u);
    // An H5Part file is not split into frames of PySPH arrays.
    auto steps = listParticleArrays(data("steps.h5part"));
    ASSERT_TRUE(steps.ok());
    EXPECT_TRUE(steps->empty());
}

TEST(PySphHdf5, OneFilePerOutputStepIsASequence) {
    REQUIRE_HDF5();
    const fs::path dir = test::tempDir() / "pysph_run";
    fs::create_directories(dir);
    for (int n : {0, 50, 100, 1000})
        fs::copy_file(data("pysph_dam_break_2d_100.hdf5"), dir / ("db_" + std::to_string(n) + ".hdf5"));
    auto frames = expandSequence(dir.string());
    ASSERT_TRUE(frames.ok()) << frames.error().describe();
    ASSERT_EQ(frames->size(), 4u);
    EXPECT_EQ(frames->back(), dir / "db_1000.hdf5");
    // A pattern of files with an array in each.
    for (const std::string& spec : {(dir / "db_*.hdf5" / "boundary").string(), (dir / "db_%d.hdf5/boundary").string()}) {
        auto arrays = expandSequence(spec);
        ASSERT_TRUE(arrays.ok()) << arrays.error().describe();
        ASSERT_EQ(arrays->size(), 4u);
        EXPECT_TRUE(isSequenceSpec(spec));
        const long numbers[] = {0, 50, 100, 1000};
        for (std::size_t i = 0; i < 4; ++i) {
            EXPECT_EQ((*arrays)[i].filename(), "boundary");
            EXPECT_EQ(frameNumberOf((*arrays)[i]), numbers[i]);
            auto set = readParticles((*arrays)[i]);
            ASSERT_TRUE(set.ok()) << set.error().describe();
            EXPECT_EQ(set->size(), 60u);
        }
    }
}

// ---------------------------------------------------------------- the CLI

TEST(Hdf5Cli, TheH5PartFrameRendersAsTheBgeoDoes) {
    REQUIRE_HDF5();
    const fs::path dir = test::tempDir() / "h5part_cli";
    fs::create_directories(dir);
    const std::string look = " --width 160 --height 120 --backend cpu";
    std::string out;
    ASSERT_EQ(test::runCli("render " + test::shellQuote(data("splishsplash_fluid21.h5part")) + " -o " +
                               test::shellQuote(dir / "h5part.png") + look,
                           &out),
              0)
        << out;
    ASSERT_EQ(test::runCli("render " + test::shellQuote(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo")) +
                               " -o " + test::shellQuote(dir / "bgeo.png") + look,
                           &out),
              0)
        << out;
    const auto a = test::readBytes(dir / "h5part.png");
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, test::readBytes(dir / "bgeo.png"));
}

TEST(Hdf5Cli, AnH5PartFileRendersEveryStepNumberedByStep) {
    REQUIRE_HDF5();
    const fs::path dir = test::tempDir() / "h5part_cli_steps";
    fs::create_directories(dir);
    std::string out;
    ASSERT_EQ(test::runCli("render " + test::shellQuote(data("steps.h5part")) + " -o " +
                               test::shellQuote(dir / "f_%04d.png") + " --width 64 --height 48 --backend cpu",
                           &out),
              0)
        << out;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"f_0000.png", "f_0001.png", "f_0002.png", "f_0010.png"})) << out;
}

TEST(Hdf5Cli, InfoReadsTheFormats) {
    REQUIRE_HDF5();
    std::string out;
    ASSERT_EQ(test::runCli("info " + test::shellQuote(data("steps.h5part")), &out), 0) << out;
    EXPECT_NE(out.find("Step#0"), std::string::npos) << out;
    EXPECT_NE(out.find("frames      4"), std::string::npos) << out;
    EXPECT_NE(out.find("particles   64"), std::string::npos) << out;
    ASSERT_EQ(test::runCli("info " + test::shellQuote(data("pysph_dam_break_2d_100.hdf5")), &out), 0) << out;
    EXPECT_NE(out.find("particles   120"), std::string::npos) << out;
    EXPECT_NE(out.find("from the smoothing length"), std::string::npos) << out;
    // Its particle arrays are listed, with how to name another.
    EXPECT_NE(out.find("arrays      boundary (60) fluid (120) (shown: the one named fluid"), std::string::npos) << out;
    EXPECT_NE(out.find("pysph_dam_break_2d_100.hdf5/NAME"), std::string::npos) << out;
    ASSERT_NE(test::runCli("info " + test::shellQuote(data("bad_step_without_x.h5part")), &out), 0);
    EXPECT_NE(out.find("bad_step_without_x.h5part/Step#0"), std::string::npos) << out;
}


#if MENISCUS_TEST_HDF5
namespace {
// An H5Part file of `times.size()` steps of two particles, each step's time
// in a double attribute named `key` (ParaView's "TimeValue", or "time").
void writeTimedH5Part(const fs::path& path, const std::vector<double>& times, const char* key) {
    const hid_t file = H5Fcreate(path.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    for (std::size_t k = 0; k < times.size(); ++k) {
        const std::string name = "Step#" + std::to_string(k);
        const hid_t group = H5Gcreate2(file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        const hid_t scalar = H5Screate(H5S_SCALAR);
        const hid_t attr = H5Acreate2(group, key, H5T_NATIVE_DOUBLE, scalar, H5P_DEFAULT, H5P_DEFAULT);
        H5Awrite(attr, H5T_NATIVE_DOUBLE, &times[k]);
        H5Aclose(attr);
        H5Sclose(scalar);
        const hsize_t n = 2;
        const hid_t space = H5Screate_simple(1, &n, nullptr);
        for (const char* axis : {"x", "y", "z"}) {
            const double v[2] = {0.0, 0.1 * double(k)};
            const hid_t d = H5Dcreate2(group, axis, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
            H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
            H5Dclose(d);
        }
        H5Sclose(space);
        H5Gclose(group);
    }
    H5Fclose(file);
}
}  // namespace

// A movie of an H5Part file plays at the rate of its steps' times, as
// ParaView reads them (each step's TimeValue); uneven or missing times give none.
TEST(H5Part, StepTimesGiveTheFrameRate) {
    REQUIRE_HDF5();
    const fs::path dir = test::tempDir();
    writeTimedH5Part(dir / "even.h5part", {0.0, 1.0 / 15, 2.0 / 15, 3.0 / 15}, "TimeValue");
    auto times = h5partStepTimes(dir / "even.h5part");
    ASSERT_TRUE(times.ok()) << times.error().describe();
    ASSERT_EQ(times->size(), 4u);
    EXPECT_DOUBLE_EQ((*times)[1], 1.0 / 15);
    auto rate = frameRateOfInput(dir / "even.h5part");
    ASSERT_TRUE(rate.ok()) << rate.error().describe();
    ASSERT_TRUE(rate->has_value());
    EXPECT_NEAR(**rate, 15.0, 1e-9);
    writeTimedH5Part(dir / "lower.h5", {2.0, 2.04, 2.08}, "time");
    rate = frameRateOfInput(dir / "lower.h5");
    ASSERT_TRUE(rate.ok() && rate->has_value());
    EXPECT_NEAR(**rate, 25.0, 1e-9);
    // steps.h5part's times (0, 0.01, 0.02, 0.1) are uneven: no rate, the default said in the log.
    rate = frameRateOfInput(data("steps.h5part"));
    ASSERT_TRUE(rate.ok());
    EXPECT_FALSE(rate->has_value());
    // A step without a time: none at all.
    writeTimedH5Part(dir / "untimed.h5part", {0.0, 0.1}, "TimeStep_not_a_time");
    times = h5partStepTimes(dir / "untimed.h5part");
    ASSERT_TRUE(times.ok());
    EXPECT_TRUE(times->empty());
}
#endif

}  // namespace
}  // namespace meniscus::io_hdf5_test_local
