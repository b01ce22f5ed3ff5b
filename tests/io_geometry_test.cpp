// Scene geometry readers (src/io/geometry.cpp): mesh files through Assimp
// (OBJ, PLY ascii and binary, STL ascii and binary, glTF 2.0 with an embedded
// buffer: tests/data/geometry/, written by make_geometry.py there), the JSON
// list of objects (parseGeometry), SPlisHSPlasH's DamBreakModel scene and its
// UnitBox model (tests/data/splishsplash_scene/, copied from SPlisHSPlasH), and
// errors that name the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "geometry_test.h"
#include "meniscus/geometry.h"
#include "test_util.h"

namespace meniscus {
namespace {

namespace fs = std::filesystem;
using test::tempDir;
using test::testData;
using test::writeText;

fs::path geo(const std::string& name) { return testData("geometry/" + name); }

template <class T>
T ok(Result<T> r) {
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().describe());
    return r.ok() ? std::move(*r) : T{};
}

template <class T>
void expectError(const Result<T>& r, const std::string& file, const std::string& word) {
    ASSERT_FALSE(r.ok()) << "no error for " << file << " (expected one with '" << word << "')";
    EXPECT_EQ(r.error().file, file) << r.error().describe();
    EXPECT_NE(r.error().message.find(word), std::string::npos) << "expected '" << word << "' in: " << r.error().describe();
}

Bounds boundsOf(const TriangleMesh& m) {
    Bounds b;
    for (const glm::vec3& p : m.positions) b.extend(p);
    return b;
}

void expectCube(const GeometryObject& o, const glm::vec3& centre) {
    ASSERT_TRUE(o.mesh.validate(true).ok()) << o.name;
    EXPECT_EQ(o.mesh.triangleCount(), 12u) << o.name;
    const Bounds b = boundsOf(o.mesh);
    EXPECT_EQ(b.min, centre - glm::vec3(1.0f)) << o.name;
    EXPECT_EQ(b.max, centre + glm::vec3(1.0f)) << o.name;
    test::expectClosedAndOriented(o.mesh);
    test::expectOutward(o.mesh, centre);
}

TEST(GeometryMesh, ObjPlyAndGltfCubesAreClosedWithOutwardNormals) {
    for (const char* name : {"cube.obj", "red_cube.obj", "cube_ascii.ply", "cube_binary.ply"}) {
        SCOPED_TRACE(name);
        const GeometryObject o = ok(readGeometryMesh(geo(name)));
        EXPECT_EQ(o.name, name);
        expectCube(o, glm::vec3(0.0f));
    }
    // The glTF node's translation is baked into the vertices.
    const GeometryObject g = ok(readGeometryMesh(geo("cube.gltf")));
    expectCube(g, glm::vec3(0.0f, 2.0f, 0.0f));
}

TEST(GeometryMesh, StlTetrahedraAsciiAndBinary) {
    for (const char* name : {"tetra_ascii.stl", "tetra_binary.stl"}) {
        SCOPED_TRACE(name);
        const GeometryObject o = ok(readGeometryMesh(geo(name)));
        ASSERT_TRUE(o.mesh.validate(true).ok());
        EXPECT_EQ(o.mesh.triangleCount(), 4u);
        const Bounds b = boundsOf(o.mesh);
        EXPECT_EQ(b.min, glm::vec3(0.0f));
        EXPECT_EQ(b.max, glm::vec3(1.0f));
        test::expectClosedAndOriented(o.mesh);
        test::expectOutward(o.mesh, glm::vec3(0.25f));
    }
}

TEST(GeometryMesh, BaseColourFromTheFile) {
    const GeometryMaterial defaults;
    // No material: our default, not Assimp's grey stand-in.
    EXPECT_EQ(ok(readGeometryMesh(geo("cube.obj"))).material, defaults);
    // An OBJ's Kd, taken as linear.
    const GeometryObject red = ok(readGeometryMesh(geo("red_cube.obj")));
    EXPECT_NEAR(red.material.baseColor.r, 0.8f, 1e-6f);
    EXPECT_NEAR(red.material.baseColor.g, 0.1f, 1e-6f);
    EXPECT_NEAR(red.material.baseColor.b, 0.05f, 1e-6f);
    // glTF's base colour factor (linear), metallic and roughness factors.
    const GeometryObject teal = ok(readGeometryMesh(geo("cube.gltf")));
    EXPECT_NEAR(teal.material.baseColor.r, 0.1f, 1e-6f);
    EXPECT_NEAR(teal.material.baseColor.g, 0.5f, 1e-6f);
    EXPECT_NEAR(teal.material.baseColor.b, 0.4f, 1e-6f);
    EXPECT_NEAR(teal.material.metalness, 0.25f, 1e-6f);
    EXPECT_NEAR(teal.material.roughness, 0.3f, 1e-6f);
}

TEST(GeometryMesh, FromMemoryTakesTheSamePath) {
    for (const char* name : {"cube.obj", "cube_binary.ply", "cube.gltf", "tetra_binary.stl"}) {
        SCOPED_TRACE(name);
        const auto bytes = test::readBytes(geo(name));
        const GeometryObject fromFile = ok(readGeometryMesh(geo(name)));
        const GeometryObject fromMemory = ok(parseGeometryMesh(ByteView(bytes.data(), bytes.size()), name));
        EXPECT_EQ(fromMemory.mesh.positions, fromFile.mesh.positions);
        EXPECT_EQ(fromMemory.mesh.indices, fromFile.mesh.indices);
    }
    // From memory no other file is opened: the .mtl is not found, the mesh still is.
    const auto bytes = test::readBytes(geo("red_cube.obj"));
    const GeometryObject o = ok(parseGeometryMesh(ByteView(bytes.data(), bytes.size()), "red_cube.obj"));
    EXPECT_EQ(o.mesh.triangleCount(), 12u);
}

TEST(GeometryMesh, BadFilesAreErrorsNamingTheFile) {
    const fs::path missing = tempDir() / "no_such_mesh.obj";
    expectError(readGeometryMesh(missing), missing.string(), "no such file");
    expectError(readGeometryMesh(geo("nan_vertex.ply")), geo("nan_vertex.ply").string(), "not finite");
    expectError(readGeometryMesh(geo("lines_only.obj")), geo("lines_only.obj").string(), "");
    expectError(readGeometryMesh(geo("broken.stl")), geo("broken.stl").string(), "cannot be read");
    const fs::path unknown = tempDir() / "mesh.xyzzy";
    writeText(unknown, "hello");
    expectError(readGeometryMesh(unknown), unknown.string(), ".obj");  // lists what Assimp reads
    const fs::path empty = tempDir() / "empty.ply";
    writeText(empty, "");
    expectError(readGeometryMesh(empty), empty.string(), "empty");
    const std::string junk = "ply\nformat ascii 1.0\nelement vertex 99999999999\nend_header\n";
    expectError(parseGeometryMesh(ByteView(reinterpret_cast<const std::uint8_t*>(junk.data()), junk.size()), "junk.ply"),
                "junk.ply", "more than the file");
    const fs::path junkFile = tempDir() / "junk.ply";
    writeText(junkFile, junk);
    expectError(readGeometryMesh(junkFile), junkFile.string(), "more than the file");
    expectError(parseGeometryMesh(ByteView(), "nothing.obj"), "nothing.obj", "empty");
}

TEST(GeometryJson, ShapesTransformsAndMaterials) {
    const std::string text = R"([
      {"box": {"min": [0, 0, 0], "max": [1, 2, 3]}, "name": "crate", "translate": [10, 0, 0],
       "material": {"color": [0.2, 0.3, 0.4], "roughness": 0.1, "metalness": 1, "glass": true, "ior": 1.33,
                    "tint": [0.9, 0.9, 1], "thickness": 0.01}},
      {"sphere": {"center": [0, 1, 0], "radius": 0.5}, "scale": 2, "visible": false},
      {"plane": {"point": [0, 0, 0], "normal": [0, 1, 0], "size": 4}, "cutaway": true},
      {"file": "cube.obj", "scale": [1, 2, 3], "rotate": {"axis": [0, 1, 0], "degrees": 90}, "translate": [0, 5, 0]}
    ])";
    const SceneGeometry g = ok(parseGeometry(text, "list.json", testData("geometry")));
    ASSERT_EQ(g.objects.size(), 4u);
    const GeometryObject& crate = g.objects[0];
    EXPECT_EQ(crate.name, "crate");
    EXPECT_EQ(boundsOf(crate.mesh).min, glm::vec3(10, 0, 0));
    EXPECT_EQ(boundsOf(crate.mesh).max, glm::vec3(11, 2, 3));
    EXPECT_TRUE(crate.material.glass);
    EXPECT_FLOAT_EQ(crate.material.ior, 1.33f);
    EXPECT_FLOAT_EQ(crate.material.metalness, 1.0f);
    EXPECT_FLOAT_EQ(crate.material.thicknessM, 0.01f);
    EXPECT_EQ(crate.material.baseColor, glm::vec3(0.2f, 0.3f, 0.4f));
    // Scaled about the origin: the centre moves too.
    const GeometryObject& ball = g.objects[1];
    EXPECT_FALSE(ball.visible);
    for (const glm::vec3& p : ball.mesh.positions) EXPECT_NEAR(glm::length(p - glm::vec3(0, 2, 0)), 1.0f, 1e-5f);
    EXPECT_TRUE(g.objects[2].cutaway);
    EXPECT_EQ(g.objects[2].mesh.triangleCount(), 2u);
    EXPECT_NEAR(boundsOf(g.objects[2].mesh).max.x, 2.0f, 1e-6f);
    // Scale (2 x 4 x 6), then a quarter turn about y (x -> -z, z -> x), then up 5.
    const GeometryObject& cube = g.objects[3];
    EXPECT_EQ(cube.name, "cube.obj");
    const Bounds b = boundsOf(cube.mesh);
    EXPECT_NEAR(b.min.x, -3.0f, 1e-5f);
    EXPECT_NEAR(b.max.x, 3.0f, 1e-5f);
    EXPECT_NEAR(b.min.y, 3.0f, 1e-5f);
    EXPECT_NEAR(b.max.y, 7.0f, 1e-5f);
    EXPECT_NEAR(b.min.z, -1.0f, 1e-5f);
    EXPECT_NEAR(b.max.z, 1.0f, 1e-5f);
    test::expectClosedAndOriented(cube.mesh);
    test::expectOutward(cube.mesh, glm::vec3(0, 5, 0));
    // The hidden sphere is not in the bounds.
    EXPECT_NEAR(g.bounds().min.y, -0.0f, 1e-5f);
}

TEST(GeometryJson, UpTurnsTheFilesUpAxisToY) {
    const SceneGeometry g = ok(parseGeometry(R"({"file": "tetra_ascii.stl", "up": [0, 0, 1]})", "inline", testData("geometry")));
    ASSERT_EQ(g.objects.size(), 1u);
    // The corner on +z is now on +y.
    const Bounds b = boundsOf(g.objects[0].mesh);
    EXPECT_NEAR(b.max.y, 1.0f, 1e-6f);
    EXPECT_NEAR(b.min.y, 0.0f, 1e-6f);
    test::expectOutward(g.objects[0].mesh, glm::vec3(0.25f, 0.25f, -0.25f));
}

TEST(GeometryJson, BadInputIsAnErrorNamingTheFileAndTheKey) {
    const fs::path dir = testData("geometry");
    struct Case {
        const char* text;
        const char* word;
    };
    const Case cases[] = {
        {R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "colour": [1,0,0]})", "colour"},
        {R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "material": {"roughness": 2}})", "material.roughness"},
        {R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "material": {"metalness": -0.5}})", "material.metalness"},
        {R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "material": {"ior": 0.5}})", "material.ior"},
        {R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "material": {"shiny": 1}})", "material.shiny"},
        {R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "scale": -1})", "scale"},
        {R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "scale": [1, 0, 1]})", "scale"},
        {R"({"box": {"min": [0,0,0], "max": [0,1,1]}})", "box.max"},
        {R"({"sphere": {"radius": 0}})", "sphere.radius"},
        {R"({"sphere": {"radius": 1e39}})", "sphere.radius"},
        {R"({"plane": {"normal": [0,0,0]}})", "plane.normal"},
        {R"({"box": {"min": [0,0,0], "max": [1,1,"1"]}})", "box.max[2]"},
        {R"({"rotate": {"axis": [0,0,0], "degrees": 3}, "sphere": {"radius": 1}})", "rotate.axis"},
        {R"([{"sphere": {"radius": 1}}, {"sphere": {"radius": 1}, "visible": 1}])", "[1].visible"},
        {R"({"name": "nothing"})", "no shape"},
        {R"({"sphere": {"radius": 1}, "box": {"min": [0,0,0], "max": [1,1,1]}})", "more than one"},
        {R"(42)", "expected"},
        {R"({"sphere": )", "JSON"},
        {R"({"splishsplash": "cube.obj"})", "splishsplash"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        expectError(parseGeometry(c.text, "scene.json", dir), "scene.json", c.word);
    }
    // A file the list names is the file the error names.
    expectError(parseGeometry(R"({"file": "nan_vertex.ply"})", "scene.json", dir), (dir / "nan_vertex.ply").string(),
                "not finite");
}

TEST(GeometryJson, DeepNestingAndHugeTextAreRefusedBeforeParsing) {
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    expectError(parseGeometry(deep, "deep.json", {}), "deep.json", "nested deeper than 64");
    // Brackets inside strings do not count.
    const std::string inString = R"({"sphere": {"radius": 1}, "name": ")" + std::string(1000, '[') + "\"}";
    EXPECT_TRUE(parseGeometry(inString, "s.json", {}).ok());
    const std::string huge(geometry_limits::kMaxJsonBytes + 1, ' ');
    expectError(parseGeometry(huge, "huge.json", {}), "huge.json", "larger than the 16 MiB a geometry JSON file may be");
}

TEST(GeometryRead, SpecIsInlineJsonAListFileOrAMeshFile) {
    const fs::path dir = testData("geometry");
    const SceneGeometry inline_ = ok(readGeometry(R"(  [{"file": "cube.obj"}])", dir));
    ASSERT_EQ(inline_.objects.size(), 1u);
    EXPECT_EQ(inline_.triangleCount(), 12u);
    const SceneGeometry mesh = ok(readGeometry("cube_ascii.ply", dir));
    ASSERT_EQ(mesh.objects.size(), 1u);
    EXPECT_EQ(mesh.objects[0].name, "cube_ascii.ply");
    // A list file: its paths are its own folder's.
    const fs::path list = tempDir() / "geometry_list.json";
    writeText(list, "[{\"file\": \"" + (dir / "cube.gltf").generic_string() +
                        "\"}, {\"sphere\": {\"radius\": 0.5}, \"name\": \"ball\"}]");
    const SceneGeometry fromFile = ok(readGeometry(list.string()));
    ASSERT_EQ(fromFile.objects.size(), 2u);
    EXPECT_EQ(fromFile.objects[1].name, "ball");
    // A list file naming itself stops at the nesting limit.
    const fs::path loop = tempDir() / "geometry_loop.json";
    writeText(loop, "{\"file\": \"geometry_loop.json\"}");
    expectError(readGeometry(loop.string()), loop.string(), "deep");
    expectError(readGeometry("no_such.obj", dir), (dir / "no_such.obj").string(), "no such file");
    expectError(readGeometry("", dir), "", "no geometry");
}

TEST(GeometrySplishSplash, DamBreakTankIsOneCutAwayBoxWhereTheSceneSaysIt) {
    const fs::path scene = testData("splishsplash_scene/scenes/DamBreakModel.json");
    const SceneGeometry g = ok(readGeometry(scene.string()));
    ASSERT_EQ(g.objects.size(), 1u);
    const GeometryObject& tank = g.objects[0];
    EXPECT_TRUE(tank.cutaway);  // isWall, mapInvert
    EXPECT_EQ(tank.name, "UnitBox.obj");
    EXPECT_EQ(tank.mesh.triangleCount(), 12u);
    // The unit box [-0.5, 0.5]^3, scaled by "scale", moved by "translation" (rotationAngle 0).
    const glm::vec3 translation(0.0f, 1.5f, 0.0f), scale(4.0f, 3.0f, 1.5f);
    const Bounds b = boundsOf(tank.mesh);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(b.min[k], translation[k] - 0.5f * scale[k], 1e-6f);
        EXPECT_NEAR(b.max[k], translation[k] + 0.5f * scale[k], 1e-6f);
    }
    test::expectClosedAndOriented(tank.mesh);
    test::expectOutward(tank.mesh, translation);
    // The file has no normals and shares its 8 corners: the generated normals
    // are split at the 90-degree edges (each face flat, one of the 6 axes),
    // not smoothed across them into a rounded look.
    for (const glm::vec3& n : tank.mesh.normals)
        EXPECT_NEAR(std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)}), 1.0f, 1e-5f) << n.x << "," << n.y << "," << n.z;
    // "color": [0.1, 0.4, 0.6, 1.0] is checked, but a wall keeps the neutral
    // default so the water reads against it (an obstacle's colour is kept:
    // RotationIsInRadiansAfterTheScale).
    EXPECT_EQ(tank.material.baseColor, GeometryMaterial{}.baseColor);
    // The same through our list's "splishsplash" key.
    const SceneGeometry viaList =
        ok(parseGeometry("{\"splishsplash\": \"" + scene.generic_string() + "\"}", "inline", {}));
    ASSERT_EQ(viaList.objects.size(), 1u);
    EXPECT_EQ(viaList.objects[0].mesh.positions, tank.mesh.positions);
}

TEST(GeometrySplishSplash, RotationIsInRadiansAfterTheScale) {
    const fs::path dir = tempDir() / "sph_scene";
    fs::create_directories(dir);
    fs::copy_file(testData("splishsplash_scene/models/UnitBox.obj"), dir / "box.obj", fs::copy_options::overwrite_existing);
    // Older scenes call them "Boundaries"; a quarter turn about z (pi/2 rad)
    // turns the scaled box (2 x 1 x 1) upright (1 x 2 x 1).
    writeText(dir / "scene.json", R"({"Boundaries": [{"geometryFile": "box.obj", "scale": [2, 1, 1],
        "rotationAxis": [0, 0, 1], "rotationAngle": 1.5707963267948966, "translation": [0, 1, 0],
        "isWall": false, "color": [0.5, 0.25, 0.0, 1.0], "particleFile": "ignored.bgeo"}]})");
    const SceneGeometry g = ok(readGeometry((dir / "scene.json").string()));
    ASSERT_EQ(g.objects.size(), 1u);
    EXPECT_FALSE(g.objects[0].cutaway);
    // An obstacle keeps its colour (sRGB as SPlisHSPlasH shows it, linear here).
    EXPECT_NEAR(g.objects[0].material.baseColor.r, 0.2140f, 1e-3f);
    EXPECT_NEAR(g.objects[0].material.baseColor.g, 0.0509f, 1e-3f);
    EXPECT_EQ(g.objects[0].material.baseColor.b, 0.0f);
    const Bounds b = boundsOf(g.objects[0].mesh);
    EXPECT_NEAR(b.min.x, -0.5f, 1e-5f);
    EXPECT_NEAR(b.max.x, 0.5f, 1e-5f);
    EXPECT_NEAR(b.min.y, 0.0f, 1e-5f);
    EXPECT_NEAR(b.max.y, 2.0f, 1e-5f);
    // A body without a geometry file, or a bad value, is an error naming the scene.
    writeText(dir / "bad.json", R"({"RigidBodies": [{"geometryFile": "box.obj", "scale": [1, "x", 1]}]})");
    expectError(readGeometry((dir / "bad.json").string()), (dir / "bad.json").string(), "RigidBodies[0].scale[1]");
    writeText(dir / "nogeo.json", R"({"RigidBodies": [{"particleFile": "a.bgeo"}]})");
    expectError(readGeometry((dir / "nogeo.json").string()), (dir / "nogeo.json").string(), "geometryFile");
}

}  // namespace
}  // namespace meniscus
