// `meniscus convert IN OUT`: every writable format round-trips a real
// SPlisHSPlasH frame with its positions bit for bit and every attribute's
// values exactly; sequences become numbered sequences; a format it cannot
// write, a bad input or an output that is the input is an error naming the
// file, with nothing written.
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "test_util.h"

namespace cli_convert_test_local {

namespace fs = std::filesystem;
using namespace meniscus;
using namespace meniscus::test;

namespace {

const char* const kWritable[] = {"vtk", "vtu", "vtp", "ply", "bgeo", "bgeo.gz"};

// The two sets hold the same positions, bit for bit, and the same attributes
// (by name, any order) with the same types and values.
void expectSameSet(const ParticleSet& a, const ParticleSet& b, const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    if (a.size() > 0) {  // (null data of an empty set: memcmp undefined)
        ASSERT_EQ(0, std::memcmp(a.positions.data(), b.positions.data(), a.size() * sizeof(glm::vec3))) << what;
    }
    ASSERT_EQ(a.attributes.size(), b.attributes.size()) << what;
    for (const Attribute& x : a.attributes) {
        const Attribute* y = b.find(x.name);
        ASSERT_NE(y, nullptr) << what << ": no attribute " << x.name;
        EXPECT_EQ(x.type, y->type) << what << ": " << x.name;
        EXPECT_EQ(x.components, y->components) << what << ": " << x.name;
        EXPECT_EQ(x.ints, y->ints) << what << ": " << x.name;
        ASSERT_EQ(x.floats.size(), y->floats.size()) << what << ": " << x.name;
        if (!x.floats.empty()) {  // memcmp of an empty vector's null data is undefined
            EXPECT_EQ(0, std::memcmp(x.floats.data(), y->floats.data(), x.floats.size() * sizeof(float)))
                << what << ": " << x.name;
        }
    }
}

ParticleSet read(const fs::path& p) {
    auto r = readParticles(p, ParticleFormat::Auto, true);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
    return r.ok() ? std::move(*r) : ParticleSet{};
}

}  // namespace

TEST(CliConvert, EveryWritableFormatRoundTripsARealFrame) {
    const fs::path dir = dirWithFrame("convert_round_trip");
    const ParticleSet original = read(dir / "f.bgeo");
    ASSERT_GT(original.size(), 1000u);
    ASSERT_NE(original.find("velocity"), nullptr);  // SPlisHSPlasH's velocity, density and id go through
    for (const char* ext : kWritable) {
        const fs::path there = dir / (std::string("there.") + ext), back = dir / (std::string("back_") + ext + ".bgeo");
        std::string out;
        ASSERT_EQ(runCli("convert " + shellQuote(dir / "f.bgeo") + " " + shellQuote(there), &out), 0) << out;
        ASSERT_EQ(runCli("convert " + shellQuote(there) + " " + shellQuote(back), &out), 0) << out;
        expectSameSet(original, read(there), ext);
        expectSameSet(original, read(back), std::string(ext) + " and back");
    }
}

TEST(CliConvert, AChainThroughEveryFormatKeepsTheFrame) {
    const fs::path dir = dirWithFrame("convert_chain");
    fs::path from = dir / "f.bgeo";
    for (const char* ext : kWritable) {
        const fs::path to = dir / (std::string("chain.") + ext);
        std::string out;
        ASSERT_EQ(runCli("convert " + shellQuote(from) + " " + shellQuote(to), &out), 0) << out;
        from = to;
    }
    expectSameSet(read(dir / "f.bgeo"), read(from), "bgeo -> vtk -> vtu -> vtp -> ply -> bgeo -> bgeo.gz");
}

TEST(CliConvert, TextColumnsBecomeAttributesThatSurviveEveryFormat) {
    const fs::path dir = tempDir() / "convert_csv";
    fs::create_directories(dir);
    writeText(dir / "p.csv", "x,y,z,vx,vy,vz,density,id,pressure\n"
                             "0.125,0.5,-1,1,2,3,998.5,7,101325\n"
                             "0.25,0.75,-1.5,-1,0,0.5,1001.25,9,99000.5\n");
    const ParticleSet csv = read(dir / "p.csv");
    ASSERT_NE(csv.find("pressure"), nullptr);
    for (const char* ext : kWritable) {
        const fs::path there = dir / (std::string("p.") + ext);
        std::string out;
        ASSERT_EQ(runCli("convert " + shellQuote(dir / "p.csv") + " " + shellQuote(there), &out), 0) << out;
        expectSameSet(csv, read(there), ext);
    }
}

TEST(CliConvert, ASequenceBecomesANumberedSequence) {
    const fs::path dir = tempDir() / "convert_sequence";
    fs::create_directories(dir / "in");
    for (const char* n : {"ParticleData_Fluid_1.bgeo", "ParticleData_Fluid_9.bgeo", "ParticleData_Fluid_21.bgeo"})
        fs::copy_file(testData(std::string("splishsplash/partio/") + n), dir / "in" / n);
    std::string out;
    // Several frames need a pattern.
    EXPECT_NE(runCli("convert " + shellQuote(dir / "in") + " " + shellQuote(dir / "one.vtu"), &out), 0);
    EXPECT_NE(out.find("%"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "one.vtu"));
    ASSERT_EQ(runCli("convert " + shellQuote(dir / "in") + " " + shellQuote(dir / "out_%03d.vtu"), &out), 0) << out;
    for (int n : {1, 9, 21}) {
        char name[32];
        std::snprintf(name, sizeof name, "out_%03d.vtu", n);
        ASSERT_TRUE(fs::exists(dir / name)) << name << "\n" << out;
        expectSameSet(read(dir / "in" / ("ParticleData_Fluid_" + std::to_string(n) + ".bgeo")), read(dir / name), name);
    }
}

TEST(CliConvert, AnEmptyFrameStaysEmpty) {
    const fs::path dir = tempDir() / "convert_empty";
    fs::create_directories(dir);
    ASSERT_TRUE(writeParticles(dir / "empty.vtu", ParticleSet{}).ok());
    std::string out;
    ASSERT_EQ(runCli("convert " + shellQuote(dir / "empty.vtu") + " " + shellQuote(dir / "empty.bgeo"), &out), 0)
        << out;
    EXPECT_EQ(read(dir / "empty.bgeo").size(), 0u);
}

TEST(CliConvert, BadRequestsAreErrorsNamingTheFileWithNothingWritten) {
    const fs::path dir = dirWithFrame("convert_errors");
    const std::string in = shellQuote(dir / "f.bgeo");
    std::string out;
    for (const char* name : {"out.csv", "out.xyz", "out.geo", "out.png", "out"}) {
        EXPECT_EQ(runCli("convert " + in + " " + shellQuote(dir / name), &out), 1) << name;
        EXPECT_NE(out.find(name), std::string::npos) << out;
        EXPECT_TRUE(out.find("cannot write") != std::string::npos || out.find("not written") != std::string::npos)
            << out;
        EXPECT_FALSE(fs::exists(dir / name)) << name;
    }
    // The output is the input (through another spelling): refused, the input kept.
    const auto before = readBytes(dir / "f.bgeo");
    EXPECT_EQ(runCli("convert " + in + " " + shellQuote(dir / "." / "f.bgeo"), &out), 1);
    EXPECT_NE(out.find("is the input"), std::string::npos) << out;
    EXPECT_EQ(readBytes(dir / "f.bgeo"), before);
    // A broken input: its name and the problem, no output.
    writeText(dir / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n");
    EXPECT_EQ(runCli("convert " + shellQuote(dir / "bad.ply") + " " + shellQuote(dir / "bad.vtu"), &out), 1);
    EXPECT_NE(out.find("bad.ply"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "bad.vtu"));
    EXPECT_NE(runCli("convert " + shellQuote(dir / "missing.bgeo") + " " + shellQuote(dir / "m.vtu"), &out), 0);
    EXPECT_NE(out.find("missing.bgeo"), std::string::npos) << out;
}

TEST(CliConvert, APvdListsTheOutputsWithTheInputsTimes) {
    const fs::path dir = tempDir() / "convert_pvd";
    fs::create_directories(dir / "in");
    fs::copy_file(testData("splishsplash/partio/ParticleData_Fluid_1.bgeo"), dir / "in" / "a_1.bgeo");
    fs::copy_file(testData("splishsplash/partio/ParticleData_Fluid_9.bgeo"), dir / "in" / "a_9.bgeo");
    writeText(dir / "in" / "series.pvd", R"(<?xml version="1.0"?>
<VTKFile type="Collection" version="0.1"><Collection>
  <DataSet timestep="0.5" part="0" file="a_9.bgeo"/>
  <DataSet timestep="0.0625" part="0" file="a_1.bgeo"/>
</Collection></VTKFile>
)");
    std::string out;
    ASSERT_EQ(runCli("convert " + shellQuote(dir / "in" / "series.pvd") + " " + shellQuote(dir / "out" / "f_%02d.vtu") +
                         " --pvd " + shellQuote(dir / "out" / "f.pvd"),
                     &out),
              0)
        << out;
    auto pvd = readPvd(dir / "out" / "f.pvd");
    ASSERT_TRUE(pvd.ok()) << pvd.error().describe();
    ASSERT_EQ(pvd->files.size(), 2u);
    EXPECT_EQ(pvd->times, (std::vector<double>{0.0625, 0.5}));
    EXPECT_EQ(pvd->files[0].filename(), "f_01.vtu");
    EXPECT_EQ(pvd->files[1].filename(), "f_09.vtu");
    // The collection reads as the sequence it lists.
    expectSameSet(read(dir / "in" / "a_9.bgeo"), read(pvd->files[1]), "through the .pvd");
    // Without a .pvd input the times are the frame numbers.
    ASSERT_EQ(runCli("convert " + shellQuote(dir / "in" / "a_*.bgeo") + " " + shellQuote(dir / "out2" / "g_%d.vtp") +
                         " --pvd " + shellQuote(dir / "out2" / "g.pvd"),
                     &out),
              0)
        << out;
    pvd = readPvd(dir / "out2" / "g.pvd");
    ASSERT_TRUE(pvd.ok()) << pvd.error().describe();
    EXPECT_EQ(pvd->times, (std::vector<double>{1, 9}));
    EXPECT_NE(runCli("convert " + shellQuote(dir / "in" / "a_1.bgeo") + " " + shellQuote(dir / "x.vtu") + " --pvd " +
                         shellQuote(dir / "x.txt"),
                     &out),
              0);
    EXPECT_NE(out.find("--pvd"), std::string::npos) << out;
}

TEST(CliConvert, TheFilesOfOtherToolsConvertWithTheirAttributes) {
    const fs::path dir = tempDir() / "convert_tools";
    fs::create_directories(dir);
    std::string out;
    // DualSPHysics CSV, boundary dropped: Type and Press kept by name, Idp as id.
    const fs::path csv = testData("dualsphysics/PartCsv_0000.csv");
    ASSERT_EQ(runCli("convert " + shellQuote(csv) + " " + shellQuote(dir / "fluid.vtu") + " --select 'Type==fluid'", &out),
              0)
        << out;
    ParticleSet all = read(csv);
    const ParticleSet fluid = read(dir / "fluid.vtu");
    ASSERT_TRUE(applySelection(all, *parseSelection("Type==fluid"), csv.string()).ok());
    expectSameSet(all, fluid, "DualSPHysics CSV, fluid only");
    ASSERT_NE(fluid.find("id"), nullptr);
    ASSERT_NE(fluid.find("Type"), nullptr);
    // An H5Part step converts under its step's number.
    const fs::path h5 = testData("hdf5/splishsplash_fluid21.h5part");
    ASSERT_EQ(runCli("convert " + shellQuote(h5) + " " + shellQuote(dir / "s_%02d.bgeo"), &out), 0) << out;
    expectSameSet(read(h5 / "Step#21"), read(dir / "s_21.bgeo"), "H5Part step 21");
    expectSameSet(read(testData("splishsplash/partio/ParticleData_Fluid_21.bgeo")), read(dir / "s_21.bgeo"),
                  "the frame the H5Part step was made from");
    // Ids beyond 32 bits (steps.h5part's 10^12 + k) cannot go into the writable formats: an error, nothing written.
    EXPECT_EQ(runCli("convert " + shellQuote(testData("hdf5/steps.h5part")) + " " + shellQuote(dir / "t_%02d.vtu"), &out), 1);
    EXPECT_NE(out.find("32-bit"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "t_00.vtu"));
    // PySPH's .npz (pickled particle dicts), its fluid array, as PLY.
    const fs::path npz = testData("hdf5/pysph_dam_break_2d_100.npz");
    ASSERT_EQ(runCli("convert " + shellQuote(npz) + " " + shellQuote(dir / "pysph.ply"), &out), 0) << out;
    expectSameSet(read(npz), read(dir / "pysph.ply"), "PySPH npz as PLY");
    ASSERT_NE(read(dir / "pysph.ply").find("h"), nullptr);  // the smoothing length goes along
}
}  // namespace cli_convert_test_local
