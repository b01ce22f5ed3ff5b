// DualSPHysics' particle output (tests/data/dualsphysics, README.txt there):
// its CSV (';' or ',', units in brackets, a trailing separator, head lines)
// and its binary legacy VTK (Vel, Rhop, Idp, Type, Mk, Press) read through the
// one alias table every reader shares (src/io/attribute_names.h), which is
// tested here on its own too; malformed files fail naming the file and line.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/attribute_names.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "test_util.h"

namespace meniscus::io_dualsphysics_test_local {
namespace {

namespace fs = std::filesystem;
using test::readBytes;
using test::tempDir;
using test::testData;
using test::writeText;

constexpr std::size_t kCount = 40;  // 8 fixed, 4 moving, 4 floating, 24 fluid (make_fixtures.py)

ParticleSet read(const std::string& rel) {
    auto r = readParticles(testData("dualsphysics/" + rel));
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
    return r.ok() ? std::move(*r) : ParticleSet{};
}

// The Type a particle of the fixtures has, from its id (JSph::SaveData's rule).
int typeOfId(std::int64_t id) { return id < 8 ? 0 : id < 12 ? 1 : id < 16 ? 2 : 3; }

// What every fixture holds, whatever the format.
void expectTank(const ParticleSet& set) {
    ASSERT_EQ(set.size(), kCount);
    // Particle 2: the floor at x = 0.04 (float32 0.039999999), density 1000.5.
    EXPECT_FLOAT_EQ(set.positions[2].x, 0.04f);
    EXPECT_EQ(set.positions[2].y, 0.0f);
    EXPECT_EQ(set.positions[2].z, 0.0f);
    // Particle 16: the first fluid particle at (0.03, 0.02, 0.02), velocity (0.5, 0, -0).
    EXPECT_FLOAT_EQ(set.positions[16].x, 0.03f);
    EXPECT_FLOAT_EQ(set.positions[16].y, 0.02f);
    EXPECT_FLOAT_EQ(set.positions[16].z, 0.02f);
    EXPECT_FLOAT_EQ(set.positions[39].z, 0.04f);

    const Attribute* id = set.find(kAttrId);
    ASSERT_NE(id, nullptr);
    EXPECT_EQ(id->type, AttributeType::Int);
    ASSERT_EQ(id->ints.size(), kCount);
    for (std::size_t i = 0; i < kCount; ++i) EXPECT_EQ(id->ints[i], std::int64_t(i));

    const Attribute* v = set.find(kAttrVelocity);
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->type, AttributeType::Float);
    ASSERT_EQ(v->components, 3);
    EXPECT_EQ(v->floats[8 * 3 + 0], 0.125f);     // the piston moves along +x
    EXPECT_EQ(v->floats[12 * 3 + 2], -0.0625f);  // the box sinks
    EXPECT_EQ(v->floats[16 * 3 + 0], 0.5f);
    EXPECT_EQ(v->floats[21 * 3 + 1], 0.03125f);  // fluid k = 5: (0.4375, 0.03125, 0)
    EXPECT_EQ(v->floats[39 * 3 + 2], -0.25f);

    const Attribute* rho = set.find(kAttrDensity);
    ASSERT_NE(rho, nullptr);
    EXPECT_EQ(rho->type, AttributeType::Float);
    EXPECT_EQ(rho->floats[2], 1000.5f);
    EXPECT_EQ(rho->floats[16], 998.0f);
    EXPECT_EQ(rho->floats[39], 1009.5f);

    // Type: 0 fixed, 1 moving, 2 floating, 3 fluid (DualSphysicsType).
    const Attribute* type = set.find("Type");
    ASSERT_NE(type, nullptr);
    ASSERT_EQ(type->count(), kCount);
    for (std::size_t i = 0; i < kCount; ++i) {
        const double t = type->type == AttributeType::Int ? double(type->ints[i]) : double(type->floats[i]);
        EXPECT_EQ(t, typeOfId(std::int64_t(i))) << i;
    }
    EXPECT_EQ(int(DualSphysicsType::Fluid), 3);
    EXPECT_EQ(int(DualSphysicsType::Fixed), 0);
}

// ---------------------------------------------------------------- CSV

TEST(DualSphysicsCsv, OwnCsvSemicolonsUnitsTrailingSeparator) {
    const ParticleSet set = read("PartCsv_0000.csv");
    expectTank(set);
    // Pos.*, Vel.*, Rho, Idp mapped; Type kept; the empty column after the
    // trailing ';' is no attribute.
    EXPECT_EQ(set.attributes.size(), 4u);
    EXPECT_EQ(set.find("Type")->type, AttributeType::Float);
}

TEST(DualSphysicsCsv, PartVtkCommaSeparatedWithHeadLinesAndPress) {
    const ParticleSet set = read("PartAll_comma_0000.csv");
    expectTank(set);
    // Rhop (the name before v5.2) is the density; Press kept by its name without the unit.
    const Attribute* press = set.find("Press");
    ASSERT_NE(press, nullptr) << "the unit ' [Pa]' is not part of the name";
    EXPECT_EQ(press->floats[0], 0.0f);
    EXPECT_NEAR(press->floats[39], 1.6e5 * (std::pow(1009.5 / 1000.0, 7) - 1.0), 0.05);
    EXPECT_EQ(set.attributes.size(), 5u);
    EXPECT_EQ(set.find("Rhop"), nullptr);
}

TEST(DualSphysicsCsv, SameParticlesAsTheVtk) {
    const ParticleSet csv = read("PartCsv_0000.csv");
    const ParticleSet vtk = read("PartAll_0000.vtk");
    ASSERT_EQ(csv.size(), vtk.size());
    EXPECT_EQ(csv.positions, vtk.positions);
    EXPECT_EQ(csv.find(kAttrVelocity)->floats, vtk.find(kAttrVelocity)->floats);
    EXPECT_EQ(csv.find(kAttrDensity)->floats, vtk.find(kAttrDensity)->floats);
    EXPECT_EQ(csv.find(kAttrId)->ints, vtk.find(kAttrId)->ints);
}

struct Parsed {
    fs::path path;
    Result<ParticleSet> result;
};

Parsed parseText(const std::string& fileName, const std::string& text) {
    const fs::path path = tempDir() / fileName;
    writeText(path, text);
    const auto data = readBytes(path);
    return {path, parseCsv(data, path.string())};
}

void expectError(const Parsed& p, const std::string& word) {
    ASSERT_FALSE(p.result.ok()) << "expected an error mentioning '" << word << "'";
    const std::string text = p.result.error().describe();
    EXPECT_NE(text.find(p.path.filename().string()), std::string::npos) << text;
    EXPECT_NE(text.find(word), std::string::npos) << "expected '" << word << "' in: " << text;
}

const char* kHeader = "Pos.x [m];Pos.y [m];Pos.z [m];Idp;Vel.x [m/s];Vel.y [m/s];Vel.z [m/s];Rhop [kg/m^3];Type;Press [Pa];\n";

TEST(DualSphysicsCsv, TrailingSeparatorOnEitherSideOnly) {
    // Header with it, rows without; then the other way round.
    const Parsed a = parseText("a.csv", std::string(kHeader) + "1;2;3;7;0.5;0;0;1000;3;12.5\n");
    ASSERT_TRUE(a.result.ok()) << a.result.error().describe();
    EXPECT_EQ(a.result->positions[0], glm::vec3(1, 2, 3));
    EXPECT_EQ(a.result->find("Press")->floats[0], 12.5f);
    const Parsed b = parseText("b.csv", "Pos.x [m];Pos.y [m];Pos.z [m];Type\n1;2;3;3;\n4;5;6;0;\n");
    ASSERT_TRUE(b.result.ok()) << b.result.error().describe();
    EXPECT_EQ(b.result->size(), 2u);
    EXPECT_EQ(b.result->find("Type")->floats, (std::vector<float>{3, 0}));
}

TEST(DualSphysicsCsv, CommaVariantAndAnyCase) {
    const Parsed p = parseText("c.csv", "POS.X [m],pos.y [m],Pos.Z [m],IDP,RHO [kg/m^3],\n1,2,3,4,999.5,\n");
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->positions[0], glm::vec3(1, 2, 3));
    EXPECT_EQ(p.result->find(kAttrId)->ints, (std::vector<std::int64_t>{4}));
    EXPECT_EQ(p.result->find(kAttrDensity)->floats, (std::vector<float>{999.5f}));
}

TEST(DualSphysicsCsvMalformed, MissingPositionColumn) {
    expectError(parseText("noz.csv", "Pos.x [m];Pos.y [m];Idp;Rhop [kg/m^3];\n1;2;3;1000;\n"), "'z'");
}

TEST(DualSphysicsCsvMalformed, BadNumberNamesTheFileLineAndColumn) {
    // Two head lines: the line number is the file's own (line 5).
    const Parsed p = parseText("bad.csv", std::string("Case\nTime: 0\n") + kHeader +
                                              "1;2;3;7;0.5;0;0;1000;3;12.5;\n1;2;3;8;0.5;0;0;1,000.0;3;12.5;\n");
    expectError(p, "line 5");
    expectError(p, "Rhop [kg/m^3]");
    expectError(p, "not a number");
}

TEST(DualSphysicsCsvMalformed, NonIntegerIdpAndShortRow) {
    expectError(parseText("idp.csv", std::string(kHeader) + "1;2;3;7.5;0.5;0;0;1000;3;12.5;\n"), "not an integer");
    const Parsed p = parseText("short.csv", std::string(kHeader) + "1;2;3;7;0.5;0;0;1000;3;12.5;\n1;2;3;8;\n");
    expectError(p, "line 3");
    expectError(p, "fields");
}

// ---------------------------------------------------------------- VTK

TEST(DualSphysicsVtk, LegacyBinaryAsJSpVtkDataWritesIt) {
    const ParticleSet set = read("PartAll_0000.vtk");
    expectTank(set);
    EXPECT_EQ(set.find("Type")->type, AttributeType::Int);  // written as short
    const Attribute* mk = set.find("Mk");
    ASSERT_NE(mk, nullptr);
    EXPECT_EQ(mk->type, AttributeType::Int);
    EXPECT_EQ(mk->ints[0], 0);
    EXPECT_EQ(mk->ints[8], 10);
    EXPECT_EQ(mk->ints[39], 1);
    ASSERT_NE(set.find("Press"), nullptr);
    for (const char* raw : {"Vel", "Rhop", "Idp"}) EXPECT_EQ(set.find(raw), nullptr) << raw;
}

// A .vtu with DualSPHysics' array names (as ParaView saves a PartVTK file):
// the XML reader maps them through the same table; ids written as floats
// become Int.
TEST(DualSphysicsVtk, VtuWithTheSameNames) {
    const std::string xml = R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="3" NumberOfCells="0">
      <PointData>
        <DataArray type="Float32" Name="Idp" format="ascii">5 6 7</DataArray>
        <DataArray type="Float32" Name="Vel" NumberOfComponents="3" format="ascii">1 2 3 4 5 6 7 8 9</DataArray>
        <DataArray type="Float32" Name="Rho" format="ascii">999 1000 1001</DataArray>
        <DataArray type="UInt8" Name="Type" format="ascii">0 3 3</DataArray>
      </PointData>
      <Points>
        <DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii"></DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii"></DataArray>
        <DataArray type="UInt8" Name="types" format="ascii"></DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
)";
    const fs::path path = tempDir() / "part.vtu";
    writeText(path, xml);
    auto r = readParticles(path);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    ASSERT_EQ(r->size(), 3u);
    ASSERT_NE(r->find(kAttrId), nullptr);
    EXPECT_EQ(r->find(kAttrId)->type, AttributeType::Int);
    EXPECT_EQ(r->find(kAttrId)->ints, (std::vector<std::int64_t>{5, 6, 7}));
    ASSERT_NE(r->find(kAttrVelocity), nullptr);
    EXPECT_EQ(r->find(kAttrVelocity)->floats[5], 6.0f);
    ASSERT_NE(r->find(kAttrDensity), nullptr);
    EXPECT_EQ(r->find(kAttrDensity)->floats[2], 1001.0f);
    ASSERT_NE(r->find("Type"), nullptr);
}

// The legacy reader with an ASCII file whose Idp holds fractions: not an id,
// kept by its own name (the table renames ids only when they are whole).
TEST(DualSphysicsVtk, FractionalIdpKeptByName) {
    const std::string text =
        "# vtk DataFile Version 3.0\nvtk output\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 1 1\n"
        "POINT_DATA 2\nSCALARS Idp float\nLOOKUP_TABLE default\n0.5 1\nFIELD FieldData 1\nRhop 1 2 float\n1000 999\n";
    const fs::path path = tempDir() / "frac.vtk";
    writeText(path, text);
    auto r = readParticles(path);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->find(kAttrId), nullptr);
    ASSERT_NE(r->find("Idp"), nullptr);
    EXPECT_EQ(r->find(kAttrDensity)->floats, (std::vector<float>{1000, 999}));
}

// ---------------------------------------------------------------- the alias table

using io_util::attributeKey;
using io_util::canonicalArrayName;
using io_util::findColumnRoles;
using io_util::withoutUnit;

TEST(AttributeNames, UnitsAndKeys) {
    EXPECT_EQ(withoutUnit("Pos.x [m]"), "Pos.x");
    EXPECT_EQ(withoutUnit("  Rhop [kg/m^3] "), "Rhop");
    EXPECT_EQ(withoutUnit("Type"), "Type");
    EXPECT_EQ(withoutUnit("[m]"), "[m]");  // nothing but a unit: kept
    EXPECT_EQ(attributeKey("Vel.X [m/s]"), "vel.x");
}

TEST(AttributeNames, CanonicalArrays) {
    EXPECT_EQ(canonicalArrayName("Vel", 3), kAttrVelocity);
    EXPECT_EQ(canonicalArrayName("Velocity", 3), kAttrVelocity);
    EXPECT_EQ(canonicalArrayName("v", 3), kAttrVelocity);
    EXPECT_EQ(canonicalArrayName("Vel", 1), "");  // a velocity has three components
    EXPECT_EQ(canonicalArrayName("Rhop", 1), kAttrDensity);
    EXPECT_EQ(canonicalArrayName("Rho [kg/m^3]", 1), kAttrDensity);
    EXPECT_EQ(canonicalArrayName("DENSITY", 1), kAttrDensity);
    EXPECT_EQ(canonicalArrayName("Idp", 1), kAttrId);
    EXPECT_EQ(canonicalArrayName("ID", 1), kAttrId);
    EXPECT_EQ(canonicalArrayName("Type", 1), "");
    EXPECT_EQ(canonicalArrayName("Press", 1), "");
    EXPECT_EQ(canonicalArrayName("h", 1), "");
}

TEST(AttributeNames, ColumnRolesOfEachTool) {
    {  // DualSPHysics
        const std::vector<std::string> names = {"Pos.x [m]", "Pos.y [m]", "Pos.z [m]", "Idp", "Vel.x [m/s]",
                                                "Vel.y [m/s]", "Vel.z [m/s]", "Rhop [kg/m^3]", "Type", ""};
        const auto r = findColumnRoles(names);
        EXPECT_EQ(r.position, (std::array<int, 3>{0, 1, 2}));
        EXPECT_EQ(r.velocity, (std::array<int, 3>{4, 5, 6}));
        EXPECT_EQ(r.density, 7);
        EXPECT_EQ(r.id, 3);
        EXPECT_FALSE(r.assigned(8));
        EXPECT_FALSE(r.assigned(9));
    }
    {  // PySPH
        const std::vector<std::string> names = {"x", "y", "z", "u", "v", "w", "rho", "h", "m"};
        const auto r = findColumnRoles(names);
        EXPECT_EQ(r.velocity, (std::array<int, 3>{3, 4, 5}));
        EXPECT_EQ(r.density, 6);
        EXPECT_EQ(r.id, -1);
    }
    {  // ParaView
        const std::vector<std::string> names = {"Velocity:0", "Velocity:1", "Velocity:2", "Points:0", "Points:1",
                                                "Points:2"};
        const auto r = findColumnRoles(names);
        EXPECT_EQ(r.position, (std::array<int, 3>{3, 4, 5}));
        EXPECT_EQ(r.velocity, (std::array<int, 3>{0, 1, 2}));
    }
    {  // Only two velocity components: no velocity; vx, vy, vz win over u v w.
        EXPECT_FALSE(findColumnRoles(std::vector<std::string>{"x", "y", "z", "vx", "vy"}).hasVelocity());
        const auto r = findColumnRoles(std::vector<std::string>{"x", "y", "z", "u", "v", "w", "vx", "vy", "vz"});
        EXPECT_EQ(r.velocity, (std::array<int, 3>{6, 7, 8}));
    }
    {  // The canonical name itself wins over an alias wherever it stands.
        const auto r = findColumnRoles(std::vector<std::string>{"x", "y", "z", "rho", "Idp", "density", "id"});
        EXPECT_EQ(r.density, 5);
        EXPECT_EQ(r.id, 6);
        EXPECT_FALSE(findColumnRoles(std::vector<std::string>{"x", "y", "density"}).hasPosition());
    }
}

Attribute floats(std::string name, int components, std::vector<float> v) {
    Attribute a;
    a.name = std::move(name);
    a.components = components;
    a.floats = std::move(v);
    return a;
}

TEST(AttributeNames, ApplyCanonicalNames) {
    std::vector<Attribute> attrs = {floats("Vel", 3, {1, 2, 3}), floats("Rhop", 1, {1000}), floats("Idp", 1, {4}),
                                    floats("Type", 1, {3})};
    io_util::applyCanonicalNames(attrs);
    EXPECT_EQ(attrs[0].name, kAttrVelocity);
    EXPECT_EQ(attrs[1].name, kAttrDensity);
    EXPECT_EQ(attrs[2].name, kAttrId);
    EXPECT_EQ(attrs[2].type, AttributeType::Int);
    EXPECT_EQ(attrs[2].ints, (std::vector<std::int64_t>{4}));
    EXPECT_EQ(attrs[3].name, "Type");

    // A file's own canonical name wins; fractional ids and integer
    // velocities are no canonical attribute.
    std::vector<Attribute> more = {floats("v", 3, {1, 2, 3}), floats("velocity", 3, {4, 5, 6}), floats("ID", 1, {0.5f})};
    Attribute intVel;
    intVel.name = "Vel";
    intVel.type = AttributeType::Int;
    intVel.components = 3;
    intVel.ints = {1, 2, 3};
    more.push_back(intVel);
    io_util::applyCanonicalNames(more);
    EXPECT_EQ(more[0].name, "v");
    EXPECT_EQ(more[1].name, kAttrVelocity);
    EXPECT_EQ(more[2].name, "ID");
    EXPECT_EQ(more[2].type, AttributeType::Float);
    EXPECT_EQ(more[3].name, "Vel");
}

TEST(AttributeNames, FloatIdsAndClashingNames) {
    Attribute whole = floats("id", 1, {0, 1, -7, 1e6f});
    EXPECT_TRUE(io_util::floatIdsToInt(whole));
    EXPECT_EQ(whole.ints, (std::vector<std::int64_t>{0, 1, -7, 1000000}));
    Attribute nan = floats("id", 1, {0, NAN});
    EXPECT_FALSE(io_util::floatIdsToInt(nan));
    EXPECT_EQ(nan.type, AttributeType::Float);
    EXPECT_EQ(io_util::nonCanonicalName("density", "_csv"), "density_csv");
    EXPECT_EQ(io_util::nonCanonicalName("Press", "_csv"), "Press");
}

// PLY goes through the same table: Rhop, Idp and Vel.x ... in a PLY header.
TEST(AttributeNames, PlyUsesTheTable) {
    const std::string text =
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
        "property float Vel.x\nproperty float Vel.y\nproperty float Vel.z\nproperty float Rhop\nproperty int Idp\n"
        "property uchar Type\nend_header\n0 0 0 1 2 3 1000 7 3\n1 1 1 4 5 6 999 8 0\n";
    const fs::path path = tempDir() / "tank.ply";
    writeText(path, text);
    auto r = readParticles(path);
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r->find(kAttrVelocity)->floats, (std::vector<float>{1, 2, 3, 4, 5, 6}));
    EXPECT_EQ(r->find(kAttrDensity)->floats, (std::vector<float>{1000, 999}));
    EXPECT_EQ(r->find(kAttrId)->ints, (std::vector<std::int64_t>{7, 8}));
    EXPECT_EQ(r->find("Type")->ints, (std::vector<std::int64_t>{3, 0}));
}

}  // namespace
}  // namespace meniscus::io_dualsphysics_test_local
