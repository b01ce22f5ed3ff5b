// The world around the liquid (docs/geometry.md): scene geometry the renderer
// draws into its scene layer before the liquid, so the liquid is depth-tested
// against it and refracts what lies behind it. Meshes from files (OBJ, PLY,
// STL, glTF 2.0 and whatever else Assimp reads), boxes, spheres and planes,
// each placed by a transform and given a material; or the rigid bodies and
// boundaries of a SPlisHSPlasH scene file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/json_text.h"
#include "meniscus/mesh.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

namespace sim {
struct Scene;
}

// Limits of the readers, checked before anything is read or allocated, so a
// hostile or broken file costs an error, not the machine's memory.
namespace geometry_limits {
// A mesh file (or a mesh in memory) larger than this is refused unread.
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t(1) << 30;  // 1 GiB
// A mesh file's triangles, all its meshes together: more is refused before
// the merged mesh is allocated (2^28 triangles are ~10 GiB as drawn).
inline constexpr std::size_t kMaxTriangles = std::size_t(1) << 28;
// A geometry JSON file or text (ours or SPlisHSPlasH's): more is refused
// unread, and nesting deeper than kMaxJsonDepth before any value is built
// (json_text.h, json_limits::kGeometry, says so for every kind of JSON).
inline constexpr std::uintmax_t kMaxJsonBytes = json_limits::kGeometry.maxBytes;  // 16 MiB
inline constexpr int kMaxJsonDepth = json_limits::kGeometry.maxDepth;
// A texture image: at most this many pixels a side and in all (2^25 pixels are
// 384 MiB as linear RGB floats), and a texture file at most this many bytes.
inline constexpr int kMaxTextureSidePx = 16384;
inline constexpr long long kMaxTexturePixels = 1LL << 25;
inline constexpr std::uintmax_t kMaxTextureFileBytes = std::uintmax_t(256) << 20;  // 256 MiB
}  // namespace geometry_limits

// A colour texture (a mesh file's base colour map) as drawn: linear RGB texels
// (decoded from the file's sRGB), row after row from the top of the image, 3
// floats each. Sampled bilinearly and repeated beyond [0, 1]
// (src/shared/texture.h), with texture coordinates (0, 0) at the image's
// bottom-left corner, as Assimp gives them for every format.
struct GeometryTexture {
    std::string name;  // the image's file (or "model.glb#0" for an embedded one), for errors and the viewer
    int width = 0, height = 0;
    std::vector<float> rgb;
};

// How a piece of geometry looks. Colours are linear RGB.
struct GeometryMaterial {
    glm::vec3 baseColor{0.62f, 0.62f, 0.6f};  // albedo of a dielectric, F0 of a metal
    float roughness = 0.55f;                  // 0 = mirror, 1 = fully diffuse
    float metalness = 0.0f;                   // 0 = dielectric, 1 = metal
    // Transparent (glass): the liquid inside is seen through it.
    bool glass = false;
    float ior = 1.5f;                          // index of refraction of the glass
    glm::vec3 tint{0.92f, 0.97f, 0.96f};       // transmittance of 1 cm of the glass (Beer-Lambert)
    float thicknessM = 0.004f;                 // wall thickness, metres (the path is longer at an angle)
    // The base colour map (opaque materials; null: none): the base colour is
    // baseColor times the texture at the surface's texture coordinates
    // (GeometryObject::uvs). Shared: objects and copies point at one image.
    std::shared_ptr<const GeometryTexture> baseColorTexture;

    bool operator==(const GeometryMaterial&) const = default;
};

// One drawn object: its triangles in the data's world coordinates (metres),
// with one unit normal per vertex.
struct GeometryObject {
    std::string name;          // the file's name or the primitive's kind, for the viewer's list and errors
    TriangleMesh mesh;
    GeometryMaterial material;
    bool visible = true;
    // A container seen from outside (a tank, a domain's walls): the faces whose
    // outside faces the camera are not drawn, so the walls between the camera
    // and the liquid are cut away and the inside of the far walls shows.
    bool cutaway = false;
    // Texture coordinates, one per mesh vertex, or none (then no texture is drawn).
    std::vector<glm::vec2> uvs;
};

struct SceneGeometry {
    std::vector<GeometryObject> objects;

    bool empty() const { return objects.empty(); }
    std::size_t triangleCount() const;
    // The box around every visible object's vertices (empty when none).
    Bounds bounds() const;
    // Appends `more`'s objects after this one's.
    void append(SceneGeometry&& more);
};

// Reads scene geometry from `spec`, which is one of:
//  - a mesh file (by extension: .obj, .ply, .stl, .gltf, .glb, .fbx, .dae,
//    .off, ... whatever Assimp reads), drawn as it is with the default material
//    or the file's own base colour;
//  - a SPlisHSPlasH scene file (.json with "RigidBodies" or "Boundaries"):
//    each body's geometry file, scale, rotation (axis and angle) and
//    translation; walls (isWall) become cut-away containers;
//  - a JSON file (.json) or inline JSON text (starting with '{' or '[') of
//    geometry objects as the scene file's `geometry` key holds them
//    (parseGeometry).
// Relative paths inside a file are taken from that file's folder; inline
// text's from `baseDir`. Errors name the file and the problem.
Result<SceneGeometry> readGeometry(const std::string& spec, const std::filesystem::path& baseDir = {});
// Whether readGeometry takes `spec` as inline JSON text: its first character
// other than blanks is '{' or '['.
bool isInlineGeometry(std::string_view spec);

// Parses the scene file's `geometry` value: one object or a list of them, as
// JSON text. `source` names where the text came from, for errors. Each object:
//   {"file": "tank.obj"} | {"box": {"min": [x,y,z], "max": [x,y,z]}}
//   | {"sphere": {"center": [x,y,z], "radius": r}}
//   | {"plane": {"point": [x,y,z], "normal": [x,y,z], "size": s}}
//   | {"splishsplash": "scene.json"}
// with optional "name", "scale" (a number or [sx,sy,sz]), "rotate"
// ({"axis": [x,y,z], "degrees": a}), "translate" ([x,y,z], metres), "up"
// (the file's up axis, [x,y,z], turned to +y), "visible", "cutaway" and
// "material" ({"color": [r,g,b] linear, "roughness", "metalness", "glass",
// "ior", "tint": [r,g,b], "thickness" in metres}). The transform is scale,
// then rotate, then translate.
Result<SceneGeometry> parseGeometry(std::string_view jsonText, const std::string& source,
                                    const std::filesystem::path& baseDir);

// A SPlisHSPlasH scene file's text, as readGeometry reads the file: its rigid
// bodies and boundaries, their geometry files taken from `baseDir`. `source`
// names the text in errors; text that is not such a scene is an error.
Result<SceneGeometry> parseSplishSplashScene(std::string_view jsonText, const std::string& source,
                                             const std::filesystem::path& baseDir);

// One mesh file through Assimp: every mesh of the file merged into one
// TriangleMesh in the file's world coordinates (its node transforms applied),
// triangles only (points and lines dropped), unit per-vertex normals; the
// material's base colour is the file's when it has one material, with its
// base colour (glTF) or diffuse (OBJ, FBX, ...) texture when it has one and
// the meshes have texture coordinates: a PNG or a JPEG, embedded in the file
// or beside it (a path relative to the file's folder). The object's name is
// the file's name. An error (naming the file)
// for a missing, unreadable, oversized or empty file, a format Assimp does not
// read, or non-finite vertices.
Result<GeometryObject> readGeometryMesh(const std::filesystem::path& file);
// The same for a file already in memory: `name` names it in errors and its
// extension (".obj", ".stl", ...) picks the format. Files the mesh refers to
// (an OBJ's .mtl, a glTF's external buffers, textures beside the file) are
// not found from memory; textures embedded in the file are read.
Result<GeometryObject> parseGeometryMesh(ByteView data, const std::string& name);

// Decodes a texture image in memory, a PNG or a JPEG (told apart by their
// signatures, whatever the name says): 8-bit sRGB samples (a 16-bit PNG
// reduced to 8 bits, grey made RGB, alpha dropped) turned linear (IEC
// 61966-2-1). `name` names the image in errors. The size is read from the
// header and checked against geometry_limits::kMaxTextureSidePx and
// kMaxTexturePixels before any pixel is allocated.
Result<GeometryTexture> decodeTexture(ByteView data, const std::string& name);

// Moves `mesh` by the affine transform `m` (positions) and its inverse
// transpose (normals, renormalised); a transform that mirrors (negative
// determinant) reverses every triangle's winding, so triangles stay
// counter-clockwise seen from outside.
void transformMesh(TriangleMesh& mesh, const glm::mat4& m);
// Gives every vertex whose normal is missing, non-finite or zero the
// area-weighted mean of its triangles' normals (+y when every one of them is
// degenerate); a mesh with no normals gets them all so.
void fillMissingNormals(TriangleMesh& mesh);

// The built-in simulator's scene as drawn geometry: one object per collider,
// where the simulator puts it (a mesh collider scaled, then translated, as
// sim::Simulator does), and the domain's walls as a cut-away box named
// "domain". An error when a mesh collider's file cannot be read.
Result<SceneGeometry> simulationGeometry(const sim::Scene& scene);

// Primitives, in world coordinates, counter-clockwise seen from outside. The
// box and the plane have flat faces (per-face vertices); the sphere shares its
// vertices, with radial normals.
TriangleMesh makeBoxMesh(const glm::vec3& min, const glm::vec3& max);
// A UV sphere whose facets are within ~0.1 % of the radius.
TriangleMesh makeSphereMesh(const glm::vec3& center, float radius);
// A square of side 2 * halfSizeM centred on `point`, facing `normal`.
TriangleMesh makePlaneMesh(const glm::vec3& point, const glm::vec3& normal, float halfSizeM);

}  // namespace meniscus
