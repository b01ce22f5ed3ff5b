// Scene geometry readers (src/io/geometry.cpp): mesh files through Assimp
// (OBJ, PLY ascii and binary, STL ascii and binary, glTF 2.0 with an embedded
// buffer: tests/data/geometry/, written by make_geometry.py there), the JSON
// list of objects (parseGeometry), SPlisHSPlasH's DamBreakModel scene and its
// UnitBox model (tests/data/splishsplash_scene/, copied from SPlisHSPlasH), and
// errors that name the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <jpeglib.h>

#include "geometry_test.h"
#include "meniscus/geometry.h"
#include "test_util.h"

namespace meniscus::io_geometry_test_local {
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

// The texel (i, j) of a texture, from its top-left corner.
glm::vec3 texel(const GeometryTexture& t, int i, int j) {
    const std::size_t k = 3 * (std::size_t(j) * std::size_t(t.width) + std::size_t(i));
    return {t.rgb[k], t.rgb[k + 1], t.rgb[k + 2]};
}

TEST(GeometryMesh, TheFilesBaseColourMapAndTextureCoordinates) {
    for (const char* name : {"textured_quad.obj", "textured_quad.gltf"}) {
        SCOPED_TRACE(name);
        const GeometryObject q = ok(readGeometryMesh(geo(name)));
        ASSERT_TRUE(q.material.baseColorTexture);
        const GeometryTexture& t = *q.material.baseColorTexture;
        ASSERT_EQ(t.width, 4);
        ASSERT_EQ(t.height, 4);
        ASSERT_EQ(t.rgb.size(), 48u);
        // sRGB 255 and 0 are linear 1 and 0 exactly.
        EXPECT_EQ(texel(t, 0, 0), glm::vec3(1, 0, 0));
        EXPECT_EQ(texel(t, 3, 0), glm::vec3(0, 1, 0));
        EXPECT_EQ(texel(t, 0, 3), glm::vec3(0, 0, 1));
        EXPECT_EQ(texel(t, 3, 3), glm::vec3(1, 1, 1));
        EXPECT_EQ(q.material.baseColor, glm::vec3(1.0f));  // the map is the colour
        // (0, 0) at the image's bottom-left for both formats: u = x, v = 1 - z.
        ASSERT_EQ(q.uvs.size(), q.mesh.positions.size());
        for (std::size_t i = 0; i < q.uvs.size(); ++i) {
            EXPECT_NEAR(q.uvs[i].x, q.mesh.positions[i].x, 1e-6f) << i;
            EXPECT_NEAR(q.uvs[i].y, 1.0f - q.mesh.positions[i].z, 1e-6f) << i;
        }
    }
    // From memory the glTF's embedded image is read; the OBJ's map beside it is not looked for.
    const auto gltf = test::readBytes(geo("textured_quad.gltf"));
    EXPECT_TRUE(ok(parseGeometryMesh(ByteView(gltf.data(), gltf.size()), "textured_quad.gltf")).material.baseColorTexture);
    const auto obj = test::readBytes(geo("textured_quad.obj"));
    EXPECT_FALSE(ok(parseGeometryMesh(ByteView(obj.data(), obj.size()), "textured_quad.obj")).material.baseColorTexture);
}

namespace {

// A CRC-32 (ISO 3309, as PNG's chunks carry), bit by bit.
std::uint32_t crc32(const std::string& bytes) {
    std::uint32_t c = 0xffffffffu;
    for (const unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}
std::string be32(std::uint32_t v) {
    return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}
// A PNG's signature, IHDR chunk for a w x h 8-bit RGB image and an empty
// IDAT chunk: a whole header, no pixels.
std::string pngHeader(std::uint32_t w, std::uint32_t h) {
    const std::string body = "IHDR" + be32(w) + be32(h) + std::string("\x08\x02\x00\x00\x00", 5);
    return std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + body + be32(crc32(body)) + be32(0) + "IDAT" +
           be32(crc32("IDAT"));
}


}  // namespace

namespace {

struct JpegBytes {
    jpeg_destination_mgr mgr;
    std::string out;
    unsigned char buffer[4096];
};

// A w x h JPEG of one colour (libjpeg, quality 95).
std::string solidJpeg(int w, int h, const unsigned char rgb[3]) {
    jpeg_compress_struct c;
    jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    JpegBytes dest;
    dest.mgr.next_output_byte = dest.buffer;
    dest.mgr.free_in_buffer = sizeof dest.buffer;
    dest.mgr.init_destination = [](j_compress_ptr) {};
    dest.mgr.empty_output_buffer = [](j_compress_ptr p) -> boolean {
        auto* d = reinterpret_cast<JpegBytes*>(p->dest);
        d->out.append(reinterpret_cast<const char*>(d->buffer), sizeof d->buffer);
        d->mgr.next_output_byte = d->buffer;
        d->mgr.free_in_buffer = sizeof d->buffer;
        return TRUE;
    };
    dest.mgr.term_destination = [](j_compress_ptr p) {
        auto* d = reinterpret_cast<JpegBytes*>(p->dest);
        d->out.append(reinterpret_cast<const char*>(d->buffer), sizeof d->buffer - d->mgr.free_in_buffer);
    };
    c.dest = &dest.mgr;
    c.image_width = JDIMENSION(w);
    c.image_height = JDIMENSION(h);
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 95, TRUE);
    jpeg_start_compress(&c, TRUE);
    std::vector<unsigned char> row(std::size_t(w) * 3);
    for (int x = 0; x < w; ++x) std::copy(rgb, rgb + 3, row.begin() + 3 * x);
    while (c.next_scanline < c.image_height) {
        JSAMPROW r = row.data();
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    return dest.out;
}

}  // namespace

TEST(GeometryMesh, TexturesBesideTheFileJpegAndBadImages) {
    const fs::path dir = tempDir();
    // The unit quad of textured_quad.obj with its map in `image`.
    auto quadWith = [&](const std::string& image) {
        const std::vector<std::uint8_t> bytes = test::readBytes(geo("textured_quad.obj"));
        std::string obj(bytes.begin(), bytes.end());
        obj.replace(obj.find("textured_quad.mtl"), 17, image + ".mtl");
        writeText(dir / (image + ".obj"), obj);
        writeText(dir / (image + ".mtl"), "newmtl checker\nmap_Kd " + image + "\n");
        return dir / (image + ".obj");
    };
    const unsigned char orange[3] = {200, 100, 50};
    writeText(dir / "orange.jpg", solidJpeg(16, 8, orange));
    const GeometryObject jpeg = ok(readGeometryMesh(quadWith("orange.jpg")));
    ASSERT_TRUE(jpeg.material.baseColorTexture);
    const GeometryTexture& t = *jpeg.material.baseColorTexture;
    EXPECT_EQ(t.width, 16);
    EXPECT_EQ(t.height, 8);
    // sRGB 200, 100, 50 in linear terms, within what JPEG's coding changes (3 codes).
    const glm::vec3 c = texel(t, 7, 4);
    EXPECT_NEAR(c.r, 0.5776f, 0.02f);
    EXPECT_NEAR(c.g, 0.1274f, 0.01f);
    EXPECT_NEAR(c.b, 0.0319f, 0.005f);

    expectError(readGeometryMesh(quadWith("missing.png")), quadWith("missing.png").string(), "missing.png");
    writeText(dir / "text.png", "not an image at all");
    expectError(readGeometryMesh(quadWith("text.png")), quadWith("text.png").string(), "not a PNG or a JPEG");
    // A header claiming 10^5 x 10^5 pixels: refused before any pixel is allocated.
    writeText(dir / "huge.png", pngHeader(100000, 100000));
    expectError(readGeometryMesh(quadWith("huge.png")), quadWith("huge.png").string(), "pixels");
    // A real header, its pixels cut off.
    writeText(dir / "cut.png", pngHeader(4, 4));
    expectError(readGeometryMesh(quadWith("cut.png")), quadWith("cut.png").string(), "PNG");
    writeText(dir / "cut.jpg", solidJpeg(16, 8, orange).substr(0, 200));
    expectError(readGeometryMesh(quadWith("cut.jpg")), quadWith("cut.jpg").string(), "JPEG");
    // A progressive JPEG's header claiming 2112 x 14856 pixels with a few
    // bytes of data behind it (found by the fuzzer): an error naming the
    // file, not 31 million grey pixels made from nothing.
    const auto nothing =
        test::readBytes(fs::path(MENISCUS_SOURCE_DIR) / "fuzz/regressions/texture/progressive_31M_pixels_no_data.jpg");
    const auto decoded = decodeTexture(ByteView(nothing.data(), nothing.size()), "nothing.jpg");
    ASSERT_FALSE(decoded.ok());
    EXPECT_NE(decoded.error().describe().find("nothing.jpg"), std::string::npos) << decoded.error().describe();
    EXPECT_NE(decoded.error().describe().find("JPEG"), std::string::npos) << decoded.error().describe();
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
}  // namespace meniscus::io_geometry_test_local
