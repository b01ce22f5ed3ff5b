// CSV and XYZ readers: column mapping (ParaView's CSV export included),
// separators, NaN tokens, and malformed files that must fail naming the file and line.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "test_util.h"

namespace meniscus::io_text_test_local {
namespace {

namespace fs = std::filesystem;
using test::readBytes;
using test::tempDir;
using test::writeText;

struct Parsed {
    fs::path path;
    Result<ParticleSet> result;
};

Parsed parseCsvText(const std::string& fileName, const std::string& text) {
    const fs::path path = tempDir() / fileName;
    writeText(path, text);
    const auto data = readBytes(path);
    return {path, parseCsv(data, path.string())};
}

Parsed parseXyzText(const std::string& fileName, const std::string& text) {
    const fs::path path = tempDir() / fileName;
    writeText(path, text);
    const auto data = readBytes(path);
    return {path, parseXyz(data, path.string())};
}

void expectError(const Parsed& p, const std::string& word) {
    ASSERT_FALSE(p.result.ok()) << "expected an error mentioning '" << word << "'";
    const std::string text = p.result.error().describe();
    EXPECT_NE(text.find(p.path.filename().string()), std::string::npos) << text;
    EXPECT_NE(text.find(word), std::string::npos) << "expected '" << word << "' in: " << text;
}

// ---------------------------------------------------------------- CSV

TEST(CsvReader, ParaViewHeaders) {
    // As ParaView's "Save Data" writes point data: quoted names, arrays' components as NAME:i.
    const std::string text =
        "\"density\",\"id\",\"Velocity:0\",\"Velocity:1\",\"Velocity:2\",\"Velocity_Magnitude\","
        "\"Points:0\",\"Points:1\",\"Points:2\"\n"
        "1000.5,7,1,2,3,3.7417,0.1,0.2,0.3\n"
        "999,8,-1,-2,-3,3.7417,1e-2,2E1,-0.5\n";
    const Parsed p = parseCsvText("paraview.csv", text);
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    ASSERT_EQ(set.size(), 2u);
    EXPECT_FLOAT_EQ(set.positions[0].x, 0.1f);
    EXPECT_FLOAT_EQ(set.positions[0].z, 0.3f);
    EXPECT_FLOAT_EQ(set.positions[1].x, 0.01f);
    EXPECT_FLOAT_EQ(set.positions[1].y, 20.0f);

    const Attribute* v = set.find(kAttrVelocity);
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->components, 3);
    EXPECT_EQ(v->floats, (std::vector<float>{1, 2, 3, -1, -2, -3}));
    const Attribute* d = set.find(kAttrDensity);
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->floats, (std::vector<float>{1000.5f, 999.0f}));
    const Attribute* id = set.find(kAttrId);
    ASSERT_NE(id, nullptr);
    EXPECT_EQ(id->type, AttributeType::Int);
    EXPECT_EQ(id->ints, (std::vector<std::int64_t>{7, 8}));
    const Attribute* mag = set.find("Velocity_Magnitude");
    ASSERT_NE(mag, nullptr);
    EXPECT_EQ(mag->type, AttributeType::Float);
    EXPECT_EQ(set.attributes.size(), 4u);
}

TEST(CsvReader, PlainColumnsAnyCaseWithSpacesAndBlankLines) {
    const std::string text =
        " X , Y , Z , VX , VY , VZ , Rho , pressure \r\n"
        "\r\n"
        "1, 2, 3, 0.5, 0, 0, 1000, 12.5\r\n"
        "   \r\n"
        "4,5,6,0,0.5,0,1001,-3\r\n";
    const Parsed p = parseCsvText("plain.csv", text);
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    ASSERT_EQ(set.size(), 2u);
    EXPECT_EQ(set.positions[1], glm::vec3(4, 5, 6));
    ASSERT_NE(set.find(kAttrVelocity), nullptr);
    EXPECT_FLOAT_EQ(set.find(kAttrVelocity)->floats[4], 0.5f);
    ASSERT_NE(set.find(kAttrDensity), nullptr);
    EXPECT_FLOAT_EQ(set.find(kAttrDensity)->floats[1], 1001.0f);
    ASSERT_NE(set.find("pressure"), nullptr);
    EXPECT_FLOAT_EQ(set.find("pressure")->floats[0], 12.5f);
}

TEST(CsvReader, SemicolonAndTabSeparators) {
    const Parsed semi = parseCsvText("semi.csv", "x;y;z;velocity_x;velocity_y;velocity_z\n1;2;3;4;5;6\n");
    ASSERT_TRUE(semi.result.ok()) << semi.result.error().describe();
    EXPECT_EQ(semi.result->positions[0], glm::vec3(1, 2, 3));
    ASSERT_NE(semi.result->find(kAttrVelocity), nullptr);
    EXPECT_FLOAT_EQ(semi.result->find(kAttrVelocity)->floats[2], 6.0f);

    const Parsed tab = parseCsvText("tab.csv", "id\tx\ty\tz\n5\t1\t2\t3\n6\t-1\t-2\t-3\n");
    ASSERT_TRUE(tab.result.ok()) << tab.result.error().describe();
    EXPECT_EQ(tab.result->positions[1], glm::vec3(-1, -2, -3));
    EXPECT_EQ(tab.result->find(kAttrId)->ints, (std::vector<std::int64_t>{5, 6}));
}

TEST(CsvReader, PartialVelocityKeptByName) {
    const Parsed p = parseCsvText("partial.csv", "x,y,z,vx,vy\n1,2,3,4,5\n");
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->find(kAttrVelocity), nullptr);
    ASSERT_NE(p.result->find("vx"), nullptr);
    EXPECT_FLOAT_EQ(p.result->find("vy")->floats[0], 5.0f);
}

TEST(CsvReader, TrailingSeparatorColumnIgnored) {
    const Parsed p = parseCsvText("trailing.csv", "x,y,z,\n1,2,3,\n4,5,6,\n");
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->size(), 2u);
    EXPECT_TRUE(p.result->attributes.empty());
}

TEST(CsvReader, NanAndInfTokensPreserved) {
    const Parsed p = parseCsvText("nan.csv", "x,y,z,density\nnan,0,0,NaN\n1,inf,-Infinity,1\n1,2,3,4\n");
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    ASSERT_EQ(set.size(), 3u);
    EXPECT_TRUE(std::isnan(set.positions[0].x));
    EXPECT_TRUE(std::isnan(set.find(kAttrDensity)->floats[0]));
    EXPECT_TRUE(std::isinf(set.positions[1].y) && set.positions[1].y > 0);
    EXPECT_TRUE(std::isinf(set.positions[1].z) && set.positions[1].z < 0);
}

TEST(CsvReader, HeaderOnlyGivesNoParticles) {
    const Parsed p = parseCsvText("header_only.csv", "x,y,z\n");
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->size(), 0u);
}

TEST(CsvMalformed, LineWithTooFewFields) {
    const Parsed p = parseCsvText("few.csv", "x,y,z\n1,2,3\n4,5\n");
    expectError(p, "line 3");
    expectError(p, "fields");
}

TEST(CsvMalformed, NonNumericField) {
    const Parsed p = parseCsvText("word.csv", "x,y,z,density\n1,2,3,4\n\n1,two,3,4\n");
    expectError(p, "line 4");
    expectError(p, "not a number");
}

TEST(CsvMalformed, EmptyFieldIsNotANumber) {
    expectError(parseCsvText("emptyfield.csv", "x,y,z\n1,,3\n"), "not a number");
}

TEST(CsvMalformed, NonIntegerId) {
    expectError(parseCsvText("id.csv", "x,y,z,id\n1,2,3,4.5\n"), "not an integer");
}

TEST(CsvMalformed, MissingZColumn) {
    expectError(parseCsvText("noz.csv", "x,y,density\n1,2,3\n"), "'z'");
}

TEST(CsvMalformed, EmptyFile) {
    expectError(parseCsvText("empty.csv", ""), "empty");
    expectError(parseCsvText("blank.csv", "\n  \n\r\n"), "empty");
}

// ---------------------------------------------------------------- XYZ

TEST(XyzReader, CommentsBlankLinesAndExtraColumns) {
    const std::string text =
        "# exported point cloud\n"
        "\n"
        "1 2 3\n"
        "  4\t5   6   0.5 0.25  # extra columns are ignored\r\n"
        "# another comment\n"
        "-7e-1 +8 9.25\n";
    const Parsed p = parseXyzText("cloud.xyz", text);
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    const ParticleSet& set = p.result.value();
    ASSERT_EQ(set.size(), 3u);
    EXPECT_EQ(set.positions[0], glm::vec3(1, 2, 3));
    EXPECT_EQ(set.positions[1], glm::vec3(4, 5, 6));
    EXPECT_FLOAT_EQ(set.positions[2].x, -0.7f);
    EXPECT_FLOAT_EQ(set.positions[2].z, 9.25f);
    EXPECT_TRUE(set.attributes.empty());
}

TEST(XyzReader, NanTokensPreserved) {
    const Parsed p = parseXyzText("nan.xyz", "nan 1 2\n3 -inf 4\n5 6 7\n");
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    ASSERT_EQ(p.result->size(), 3u);
    EXPECT_TRUE(std::isnan(p.result->positions[0].x));
    EXPECT_TRUE(std::isinf(p.result->positions[1].y));
}

TEST(XyzReader, CommentsOnlyGivesNoParticles) {
    const Parsed p = parseXyzText("comments.xyz", "# nothing here\n\n");
    ASSERT_TRUE(p.result.ok()) << p.result.error().describe();
    EXPECT_EQ(p.result->size(), 0u);
}

TEST(XyzMalformed, NonNumericWithLineNumber) {
    const Parsed p = parseXyzText("word.xyz", "# header\n1 2 3\n1 b 3\n");
    expectError(p, "line 3");
    expectError(p, "not a number");
}

TEST(XyzMalformed, TooFewCoordinates) {
    const Parsed p = parseXyzText("short.xyz", "1 2 3\n4 5\n");
    expectError(p, "line 2");
    expectError(p, "expected 3");
}

TEST(XyzMalformed, EmptyFile) { expectError(parseXyzText("empty.xyz", ""), "empty"); }

}  // namespace
}  // namespace meniscus::io_text_test_local
