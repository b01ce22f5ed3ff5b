// The world around the liquid (docs/geometry.md): scene geometry the renderer
// draws into its scene layer before the liquid, so the liquid is depth-tested
// against it and refracts what lies behind it. Meshes from files (OBJ, PLY,
// STL, glTF 2.0 and whatever else Assimp reads), boxes, spheres and planes,
// each placed by a transform and given a material; or the rigid bodies and
// boundaries of a SPlisHSPlasH scene file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/mesh.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// How a piece of geometry looks. Colours are linear RGB.
struct GeometryMaterial {
    glm::vec3 baseColor{0.62f, 0.62f, 0.6f};  // albedo of a dielectric, F0 of a metal
    float roughness = 0.55f;                  // 0 = mirror, 1 = fully diffuse
    float metalness = 0.0f;                   // 0 = dielectric, 1 = metal
    // Transparent (glass): the liquid inside is seen through it.
    bool glass = false;
    float ior = 1.5f;                          // index of refraction of the glass
    glm::vec3 tint{0.92f, 0.97f, 0.96f};       // transmittance through `thicknessM` of glass
    float thicknessM = 0.004f;                 // wall thickness, metres

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

// Primitives, in world coordinates, with flat faces (per-face vertices).
TriangleMesh makeBoxMesh(const glm::vec3& min, const glm::vec3& max);
// A UV sphere whose facets are within ~0.1 % of the radius.
TriangleMesh makeSphereMesh(const glm::vec3& center, float radius);
// A square of side 2 * halfSizeM centred on `point`, facing `normal`.
TriangleMesh makePlaneMesh(const glm::vec3& point, const glm::vec3& normal, float halfSizeM);

}  // namespace meniscus
