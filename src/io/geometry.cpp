// Scene geometry readers (include/meniscus/geometry.h, docs/geometry.md): mesh
// files through Assimp, our JSON list of objects, and SPlisHSPlasH scene files'
// rigid bodies and boundaries. Every error names the file and the problem;
// nothing throws through the API (Assimp and nlohmann-json are fenced in here).
#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <new>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "io/containers.h"
#include "meniscus/geometry.h"
#include "meniscus/io.h"
#include "meniscus/json_text.h"
#include "shared/text_lines.h"
#include "shared/finite.h"
#include "io/io_util.h"

namespace meniscus {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
namespace lim = geometry_limits;

using io_util::lower;

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}


// sRGB-encoded [0, 1] to linear (IEC 61966-2-1).
float srgbToLinear(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// ---------------------------------------------------------------- Assimp

// Post-processing: polygons to triangles, shared vertices joined (so smooth
// normals are smooth), normals where the file has none, node transforms baked
// into the vertices (world coordinates, one flat list of meshes), meshes split
// by primitive type so points and lines can be dropped, and Assimp's own
// check of the structure (index ranges) before we look at it.
// The crease angle of generated normals (importWith), degrees.
constexpr float kCreaseDegrees = 45.0f;
constexpr unsigned kAssimpFlags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_GenSmoothNormals | aiProcess_PreTransformVertices |
                                  aiProcess_SortByPType | aiProcess_ValidateDataStructure;

// For a file read from memory: no other file can be opened (an OBJ's mtllib,
// a glTF's external buffer), so what is read depends on the bytes given alone.
class NoFiles : public Assimp::IOSystem {
public:
    bool Exists(const char*) const override { return false; }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char*, const char*) override { return nullptr; }
    void Close(Assimp::IOStream* stream) override { delete stream; }
};

std::string supportedList(const Assimp::Importer& importer) {
    std::string list;
    importer.GetExtensionList(list);  // "*.3ds;*.obj;..."
    std::string out;
    for (std::size_t i = 0; i < list.size(); ++i) {
        if (list[i] == '*') continue;
        out += list[i] == ';' ? ' ' : list[i];
    }
    return out;
}

std::optional<glm::vec3> materialColor(const aiMaterial* m) {
    aiColor4D c;
    // glTF's base colour factor (linear, as glTF stores it), else the diffuse
    // colour: an OBJ's Kd, which we take as linear as most renderers and
    // exporters do (the MTL format says nothing about its encoding).
    if (m->Get(AI_MATKEY_BASE_COLOR, c) != aiReturn_SUCCESS && m->Get(AI_MATKEY_COLOR_DIFFUSE, c) != aiReturn_SUCCESS)
        return std::nullopt;
    const glm::vec3 v(c.r, c.g, c.b);
    if (!finite3(v)) return std::nullopt;
    return glm::clamp(v, glm::vec3(0.0f), glm::vec3(1.0f));
}

// The texture at `path` of material of `scene` read from `name`: embedded
// ("*0", or a name the file's own textures carry), else a file relative to
// the model's folder, read when `fromDisk` (from memory none is found: null).
Result<std::shared_ptr<const GeometryTexture>> readTexture(const aiScene* scene, const std::string& path,
                                                           const std::string& name, bool fromDisk) {
    using Shared = std::shared_ptr<const GeometryTexture>;
    if (const aiTexture* t = scene->GetEmbeddedTexture(path.c_str())) {
        const std::string label = fs::path(name).filename().string() + "#" + path;
        if (t->mHeight == 0) {  // compressed: mWidth bytes of a PNG, a JPEG, ...
            if (!t->pcData) return makeError(name, "its embedded texture " + path + " has no data");
            auto img = decodeTexture(ByteView(reinterpret_cast<const std::uint8_t*>(t->pcData), t->mWidth), label);
            if (!img) return makeError(name, "its texture " + img.error().file + " " + img.error().message);
            return Shared(std::make_shared<GeometryTexture>(std::move(*img)));
        }
        // Raw texels, BGRA bytes, sRGB like any colour map.
        if (t->mWidth > unsigned(lim::kMaxTextureSidePx) || t->mHeight > unsigned(lim::kMaxTextureSidePx) ||
            (long long)t->mWidth * t->mHeight > lim::kMaxTexturePixels || !t->pcData)
            return makeError(name, "its embedded texture " + path + " is too large or has no data");
        GeometryTexture out;
        out.name = label;
        out.width = int(t->mWidth);
        out.height = int(t->mHeight);
        out.rgb.resize(std::size_t(t->mWidth) * t->mHeight * 3);
        for (std::size_t i = 0; i < std::size_t(t->mWidth) * t->mHeight; ++i) {
            const aiTexel& x = t->pcData[i];
            out.rgb[3 * i] = srgbToLinear(float(x.r) / 255.0f);
            out.rgb[3 * i + 1] = srgbToLinear(float(x.g) / 255.0f);
            out.rgb[3 * i + 2] = srgbToLinear(float(x.b) / 255.0f);
        }
        return Shared(std::make_shared<GeometryTexture>(std::move(out)));
    }
    if (!fromDisk) return Shared();
    std::string rel = path;
    std::replace(rel.begin(), rel.end(), '\\', '/');  // Windows exporters' separators
    const fs::path file = fs::path(name).parent_path() / rel;
    const std::string shown = file.string();
    // Read whole within the cap, refused unread beyond it (io_util::readFileChecked).
    auto bytes = io_util::readFileChecked(file, lim::kMaxTextureFileBytes, nullptr);
    if (!bytes) return makeError(name, "its texture " + shown + ": " + bytes.error().message);
    auto img = decodeTexture(*bytes, shown);
    if (!img) return makeError(name, "its texture " + shown + " " + img.error().message);
    return Shared(std::make_shared<GeometryTexture>(std::move(*img)));
}

// The meshes of an imported scene as one object (see readGeometryMesh).
Result<GeometryObject> toObject(const aiScene* scene, const std::string& name, bool fromDisk) {
    if (!scene || !scene->mMeshes || scene->mNumMeshes == 0)
        return makeError(name, "has no meshes");
    // Count first, so the cap is checked before anything is allocated.
    std::size_t triangles = 0, vertices = 0;
    std::optional<unsigned> material;
    bool oneMaterial = true;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const aiMesh* m = scene->mMeshes[i];
        if (!m || !(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !m->mFaces || !m->mVertices) continue;
        std::size_t own = 0;
        for (unsigned f = 0; f < m->mNumFaces; ++f) own += m->mFaces[f].mNumIndices == 3;
        if (own == 0) continue;
        triangles += own;
        vertices += m->mNumVertices;
        if (triangles > lim::kMaxTriangles)
            return makeError(name, "has more than " + std::to_string(lim::kMaxTriangles) + " triangles (the limit)");
        if (material && *material != m->mMaterialIndex) oneMaterial = false;
        material = m->mMaterialIndex;
    }
    if (triangles == 0) return makeError(name, "has no triangles (points and lines are not drawn)");
    if (vertices > std::size_t(0xffffffffu))
        return makeError(name, "has more than 2^32 - 1 vertices");

    GeometryObject obj;
    obj.name = fs::path(name).filename().string();
    // The one material's base colour map (glTF's base colour, else the
    // diffuse map), drawn when some mesh has texture coordinates.
    const aiMaterial* mat = oneMaterial && material && scene->mMaterials && *material < scene->mNumMaterials
                                ? scene->mMaterials[*material]
                                : nullptr;
    aiString matName;
    // Assimp's own stand-in (a file without materials: an OBJ without
    // .mtl, STL, PLY) keeps our default rather than its 0.6 grey.
    if (mat && mat->Get(AI_MATKEY_NAME, matName) == aiReturn_SUCCESS &&
        std::strcmp(matName.C_Str(), AI_DEFAULT_MATERIAL_NAME) == 0)
        mat = nullptr;
    bool anyUv = false;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i)
        anyUv = anyUv || (scene->mMeshes[i] && scene->mMeshes[i]->HasTextureCoords(0));
    aiString texPath;
    if (mat && anyUv &&
        (mat->GetTexture(aiTextureType_BASE_COLOR, 0, &texPath) == aiReturn_SUCCESS ||
         mat->GetTexture(aiTextureType_DIFFUSE, 0, &texPath) == aiReturn_SUCCESS) &&
        texPath.length > 0) {
        auto tex = readTexture(scene, texPath.C_Str(), name, fromDisk);
        if (!tex) return tex.error();
        obj.material.baseColorTexture = std::move(*tex);
    }
    const bool withUv = obj.material.baseColorTexture != nullptr;
    if (withUv) obj.uvs.reserve(vertices);
    TriangleMesh& out = obj.mesh;
    out.positions.reserve(vertices);
    out.normals.reserve(vertices);
    out.indices.reserve(triangles * 3);
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const aiMesh* m = scene->mMeshes[i];
        if (!m || !(m->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !m->mFaces || !m->mVertices) continue;
        const auto base = std::uint32_t(out.positions.size());
        bool any = false;
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const aiFace& face = m->mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (unsigned k = 0; k < 3; ++k) {
                if (face.mIndices[k] >= m->mNumVertices)
                    return makeError(name, "mesh " + std::to_string(i) + " has a vertex index out of range");
                out.indices.push_back(base + face.mIndices[k]);
            }
            any = true;
        }
        if (!any) continue;
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            const aiVector3D& p = m->mVertices[v];
            const glm::vec3 q(p.x, p.y, p.z);
            if (!finite3(q))
                return makeError(name, "vertex " + std::to_string(v) + " of mesh " + std::to_string(i) +
                                           " is not finite (" + num(p.x) + ", " + num(p.y) + ", " + num(p.z) + ")");
            out.positions.push_back(q);
            if (m->mNormals) out.normals.emplace_back(m->mNormals[v].x, m->mNormals[v].y, m->mNormals[v].z);
            else out.normals.emplace_back(0.0f);
            if (withUv) {
                glm::vec2 uv(0.0f);
                if (m->HasTextureCoords(0)) uv = {m->mTextureCoords[0][v].x, m->mTextureCoords[0][v].y};
                obj.uvs.push_back(std::isfinite(uv.x) && std::isfinite(uv.y) ? uv : glm::vec2(0.0f));
            }
        }
    }
    // Assimp leaves NaN normals on vertices of degenerate faces; those (and
    // any other unusable one) get the mean of their triangles' normals.
    fillMissingNormals(out);

    if (mat) {
        if (auto c = materialColor(mat)) obj.material.baseColor = *c;
        // A textured OBJ's Kd is often left at Assimp's 0.6 grey or black
        // beside its map_Kd; the map is the colour then (glTF multiplies its
        // factor, 1 by default, with the map, as here).
        if (obj.material.baseColorTexture) {
            aiColor4D factor;
            if (mat->Get(AI_MATKEY_BASE_COLOR, factor) == aiReturn_SUCCESS) {
                if (auto c = materialColor(mat)) obj.material.baseColor = *c;
            } else {
                obj.material.baseColor = glm::vec3(1.0f);
            }
        }
        float f = 0.0f;
        if (mat->Get(AI_MATKEY_METALLIC_FACTOR, f) == aiReturn_SUCCESS && std::isfinite(f))
            obj.material.metalness = std::clamp(f, 0.0f, 1.0f);
        if (mat->Get(AI_MATKEY_ROUGHNESS_FACTOR, f) == aiReturn_SUCCESS && std::isfinite(f))
            obj.material.roughness = std::clamp(f, 0.0f, 1.0f);
    }
    if (Status st = out.validate(true); !st) return makeError(name, st.error().message);
    return obj;
}

// The one path both readers take: `read` calls ReadFile or ReadFileFromMemory
// (with aiProcess_ValidateDataStructure only; the rest, kAssimpFlags, after the check).
template <class Read>
Result<GeometryObject> importWith(Assimp::Importer& importer, const std::string& name, bool fromDisk, Read&& read) {
    try {
        // Points and lines are split off by SortByPType, then dropped.
        importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
        // Normals made for a file without them are smooth only across edges
        // of at most kCreaseDegrees (a sphere's facets), and split at sharper
        // ones (a box's corners), so a box is drawn with flat faces.
        importer.SetPropertyFloat(AI_CONFIG_PP_GSN_MAX_SMOOTHING_ANGLE, kCreaseDegrees);
        auto failed = [&] {
            const char* why = importer.GetErrorString();
            return makeError(name, std::string("cannot be read: ") + (why && *why ? why : "unknown Assimp error"));
        };
        // Read as the file is (validated), look for non-finite vertices, then
        // post-process: joining identical vertices compares with ==, so a NaN
        // vertex would be merged away into a degenerate triangle unseen.
        const aiScene* raw = read();
        if (!raw) return failed();
        for (unsigned i = 0; raw->mMeshes && i < raw->mNumMeshes; ++i) {
            const aiMesh* m = raw->mMeshes[i];
            if (!m || !m->mVertices) continue;
            for (unsigned v = 0; v < m->mNumVertices; ++v) {
                const aiVector3D& p = m->mVertices[v];
                if (!finite3(glm::vec3(p.x, p.y, p.z)))
                    return makeError(name, "vertex " + std::to_string(v) + " of mesh " + std::to_string(i) +
                                               " is not finite (" + num(p.x) + ", " + num(p.y) + ", " + num(p.z) + ")");
            }
        }
        const aiScene* scene = importer.ApplyPostProcessing(kAssimpFlags & ~unsigned(aiProcess_ValidateDataStructure));
        if (!scene) return failed();
        return toObject(scene, name, fromDisk);
    } catch (const std::bad_alloc&) {
        return makeError(name, "ran out of memory while reading");
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot be read: ") + e.what());
    } catch (...) {
        return makeError(name, "cannot be read (an unknown error inside Assimp)");
    }
}

std::string extensionOf(const std::string& name) { return lower(fs::path(name).extension().string()); }

// A PLY header's element counts, checked against the file's size before
// Assimp sees them: every element takes at least one byte in any encoding, so
// a count above the size is a broken or hostile file, which Assimp's PLY
// reader would otherwise loop over (a 60-byte file claiming 10^11 vertices
// takes it most of a minute).
std::optional<std::string> implausiblePly(std::string_view head, std::uintmax_t size) {
    if (head.substr(0, 3) != "ply") return std::nullopt;
    shared::TextLines lines(head);
    for (std::string_view line; lines.next(line);) {
        if (line.substr(0, 10) == "end_header") break;
        if (line.substr(0, 8) != "element ") continue;
        const std::size_t space = line.rfind(' ');
        const std::string count(line.substr(space + 1));
        char* stop = nullptr;
        const double n = std::strtod(count.c_str(), &stop);
        if (n > double(size))
            return "its header claims " + count + " " + std::string(line.substr(8, space > 8 ? space - 8 : 0)) +
                   " elements, more than the file's " + std::to_string(size) + " bytes can hold";
    }
    return std::nullopt;
}

// Why a mesh of `size` bytes named `name` is refused before it is read (empty,
// over the size limit, or an extension Assimp does not read); none: read it.
std::optional<Error> refusedMesh(const Assimp::Importer& importer, const std::string& name, const std::string& ext,
                                 std::uintmax_t size) {
    if (size == 0) return makeError(name, "is empty");
    if (size > lim::kMaxMeshFileBytes)
        return makeError(name, "is " + std::to_string(size) + " bytes; a mesh file is at most " +
                                   std::to_string(lim::kMaxMeshFileBytes) + " bytes");
    if (ext.empty() || !importer.IsExtensionSupported(ext))
        return makeError(name, "is not a mesh format this build reads (by its extension " +
                                   (ext.empty() ? std::string("(none)") : ext) + "); Assimp reads " +
                                   supportedList(importer));
    return std::nullopt;
}

}  // namespace

Result<GeometryObject> readGeometryMesh(const fs::path& file) {
    const std::string name = file.string();
    try {
        std::error_code ec;
        if (!fs::exists(file, ec)) return makeError(name, "no such file");
        if (!fs::is_regular_file(file, ec)) return makeError(name, "is not a regular file");
        const std::uintmax_t size = fs::file_size(file, ec);
        if (ec) return makeError(name, "cannot be read: " + ec.message());
        Assimp::Importer importer;
        const std::string ext = extensionOf(name);
        if (auto refused = refusedMesh(importer, name, ext, size)) return *refused;
        if (ext == ".ply") {
            std::ifstream in(file, std::ios::binary);
            std::string head(std::size_t(std::min<std::uintmax_t>(size, 64 << 10)), '\0');
            in.read(head.data(), std::streamsize(head.size()));
            head.resize(std::size_t(in.gcount()));
            if (auto why = implausiblePly(head, size)) return makeError(name, *why);
        }
        return importWith(importer, name, true, [&] { return importer.ReadFile(name, aiProcess_ValidateDataStructure); });
    } catch (...) {
        return makeError(name, "cannot be read (an unexpected error)");
    }
}

Result<GeometryObject> parseGeometryMesh(ByteView data, const std::string& name) {
    try {
        Assimp::Importer importer;
        const std::string ext = extensionOf(name);
        if (auto refused = refusedMesh(importer, name, ext, data.size())) return *refused;
        if (ext == ".ply") {
            const std::string_view head(reinterpret_cast<const char*>(data.data()), std::min<std::size_t>(data.size(), 64 << 10));
            if (auto why = implausiblePly(head, data.size())) return makeError(name, *why);
        }
        importer.SetIOHandler(new NoFiles);  // the importer owns it
        const std::string hint = ext.substr(1);
        return importWith(importer, name, false, [&] {
            return importer.ReadFileFromMemory(data.data(), data.size(), aiProcess_ValidateDataStructure, hint.c_str());
        });
    } catch (...) {
        return makeError(name, "cannot be read (an unexpected error)");
    }
}

// ---------------------------------------------------------------- JSON

namespace {

// Thrown inside the JSON readers, caught at their door: the file, the key
// path (`[1].material.roughness`) and what is wrong. A wrong value or key of a
// geometry list (fail) is an error in the caller's settings (Error::usage: the
// CLI exits 2, as for any option's value); a mesh or texture file that cannot
// be read keeps the kind its reader gave it (the data's: exit 1).
struct Failure {
    std::string file;
    std::string message;
    bool usage = true;
};
[[noreturn]] void failAt(const std::string& file, const std::string& path, const std::string& message) {
    throw Failure{file, path.empty() ? message : path + ": " + message};
}

std::string shown(std::string_view key) {
    return key.size() <= 64 ? std::string(key) : std::string(key.substr(0, 61)) + "...";
}
std::string child(const std::string& path, std::string_view key) {
    return path.empty() ? shown(key) : path + "." + shown(key);
}
std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// Size and nesting are checked before nlohmann-json builds anything
// (json_text.h: the limits of geometry JSON).
json parseJson(std::string_view text, const std::string& source) {
    if (auto fits = checkJsonText(text, source, json_limits::kGeometry); !fits) failAt(source, "", fits.error().message);
    try {
        return json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        failAt(source, "", std::string("not valid JSON: ") + e.what());
    }
}

// Typed reads; `path` names the value in errors.
struct Reader {
    std::string file;

    std::string typeOf(const json& v) const { return v.is_null() ? "null" : std::string(v.type_name()); }

    float number(const json& v, const std::string& path) const {
        if (!v.is_number()) failAt(file, path, "expected a number, got " + typeOf(v));
        const double d = v.get<double>();
        if (!std::isfinite(d) || std::abs(d) > double(FLT_MAX)) failAt(file, path, "not a finite number: " + num(d));
        return float(d);
    }
    bool boolean(const json& v, const std::string& path) const {
        if (!v.is_boolean()) failAt(file, path, "expected true or false, got " + typeOf(v));
        return v.get<bool>();
    }
    std::string string(const json& v, const std::string& path) const {
        if (!v.is_string()) failAt(file, path, "expected a string, got " + typeOf(v));
        std::string s = v.get<std::string>();
        if (s.empty()) failAt(file, path, "is empty");
        return s;
    }
    glm::vec3 vec3(const json& v, const std::string& path) const {
        if (!v.is_array() || v.size() != 3) failAt(file, path, "expected three numbers [x, y, z], got " + typeOf(v));
        return {number(v[0], element(path, 0)), number(v[1], element(path, 1)), number(v[2], element(path, 2))};
    }
    const json& object(const json& v, const std::string& path) const {
        if (!v.is_object()) failAt(file, path, "expected an object {...}, got " + typeOf(v));
        return v;
    }
    // Every key of `o` must be one of `known`.
    void onlyKeys(const json& o, const std::string& path, std::initializer_list<const char*> known) const {
        for (auto it = o.begin(); it != o.end(); ++it) {
            const bool ok = std::any_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; });
            if (!ok) {
                std::string list;
                for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
                failAt(file, child(path, it.key()), "unknown key (known here: " + list + ")");
            }
        }
    }
};

glm::mat4 rotation(const glm::vec3& axis, float radians) {
    if (radians == 0.0f) return glm::mat4(1.0f);
    return glm::rotate(glm::mat4(1.0f), radians, glm::normalize(axis));
}

// The rotation that turns the unit vector `up` to +y (Rodrigues), half a turn
// about x when it points down.
glm::mat4 upToY(const glm::vec3& upAxis) {
    const glm::vec3 n = glm::normalize(upAxis), y(0, 1, 0);
    const glm::vec3 a = glm::cross(n, y);
    const float s = glm::length(a), c = glm::dot(n, y);
    if (s < 1e-7f) return c > 0.0f ? glm::mat4(1.0f) : glm::rotate(glm::mat4(1.0f), std::numbers::pi_v<float>, glm::vec3(1, 0, 0));
    return glm::rotate(glm::mat4(1.0f), std::atan2(s, c), a / s);
}

void applyMaterial(const Reader& r, const json& m, const std::string& path, GeometryMaterial& out) {
    r.object(m, path);
    r.onlyKeys(m, path, {"color", "roughness", "metalness", "glass", "ior", "tint", "thickness"});
    auto unitColor = [&](const char* key, glm::vec3& dst) {
        if (!m.contains(key)) return;
        const glm::vec3 c = r.vec3(m[key], child(path, key));
        for (int i = 0; i < 3; ++i)
            if (c[i] < 0.0f || c[i] > 1.0f)
                failAt(r.file, element(child(path, key), std::size_t(i)), "must be in [0, 1] (linear RGB), got " + num(c[i]));
        dst = c;
    };
    auto ranged = [&](const char* key, float lo, float hi, float& dst) {
        if (!m.contains(key)) return;
        const float v = r.number(m[key], child(path, key));
        if (v < lo || v > hi) failAt(r.file, child(path, key), "must be in [" + num(lo) + ", " + num(hi) + "], got " + num(v));
        dst = v;
    };
    unitColor("color", out.baseColor);
    unitColor("tint", out.tint);
    ranged("roughness", 0.0f, 1.0f, out.roughness);
    ranged("metalness", 0.0f, 1.0f, out.metalness);
    ranged("ior", 1.0f, 3.0f, out.ior);
    if (m.contains("glass")) out.glass = r.boolean(m["glass"], child(path, "glass"));
    if (m.contains("thickness")) {
        const float t = r.number(m["thickness"], child(path, "thickness"));
        if (!(t > 0.0f)) failAt(r.file, child(path, "thickness"), "must be > 0 metres, got " + num(t));
        out.thicknessM = t;
    }
}

SceneGeometry readSplishSplash(const json& root, const std::string& file, const fs::path& folder);
SceneGeometry readGeometryFile(const fs::path& path, int nesting, bool splishSplashOnly = false);
SceneGeometry parseList(const json& root, const std::string& source, const fs::path& baseDir, int nesting);

// A file a list names may name other files (a .json list, a SPlisHSPlasH
// scene): so deep and no deeper, so a file naming itself is an error.
constexpr int kMaxFileNesting = 8;

fs::path resolve(const fs::path& baseDir, const std::string& name) {
    const fs::path p(name);
    return p.is_relative() && !baseDir.empty() ? baseDir / p : p;
}

GeometryObject checkedMesh(Result<GeometryObject> r) {
    if (!r) throw Failure{r.error().file, r.error().message, r.error().usage};
    return std::move(r.value());
}

SceneGeometry parseObject(const Reader& r, const json& o, const std::string& path, const fs::path& baseDir,
                          int nesting) {
    r.object(o, path);
    r.onlyKeys(o, path, {"file", "box", "sphere", "plane", "splishsplash", "name", "scale", "rotate", "translate",
                         "up", "visible", "cutaway", "material"});
    int kinds = 0;
    for (const char* k : {"file", "box", "sphere", "plane", "splishsplash"}) kinds += o.contains(k);
    if (kinds != 1)
        failAt(r.file, path, kinds == 0 ? "no shape: expected one of \"file\", \"box\", \"sphere\", \"plane\", \"splishsplash\""
                                      : "more than one of \"file\", \"box\", \"sphere\", \"plane\", \"splishsplash\"");

    // The transform first, so a bad one is reported before any file is read.
    glm::mat4 m(1.0f);
    if (o.contains("up")) {
        const glm::vec3 up = r.vec3(o["up"], child(path, "up"));
        if (!(glm::dot(up, up) > 0.0f)) failAt(r.file, child(path, "up"), "must not be [0, 0, 0]");
        m = upToY(up);
    }
    if (o.contains("scale")) {
        const std::string p = child(path, "scale");
        const glm::vec3 s = o["scale"].is_array() ? r.vec3(o["scale"], p) : glm::vec3(r.number(o["scale"], p));
        for (int i = 0; i < 3; ++i)
            if (!(s[i] > 0.0f)) failAt(r.file, p, "must be > 0, got " + num(s[i]));
        m = glm::scale(glm::mat4(1.0f), s) * m;
    }
    if (o.contains("rotate")) {
        const std::string p = child(path, "rotate");
        const json& rot = r.object(o["rotate"], p);
        r.onlyKeys(rot, p, {"axis", "degrees"});
        if (!rot.contains("axis") || !rot.contains("degrees")) failAt(r.file, p, "needs \"axis\" and \"degrees\"");
        const glm::vec3 axis = r.vec3(rot["axis"], child(p, "axis"));
        if (!(glm::dot(axis, axis) > 0.0f)) failAt(r.file, child(p, "axis"), "must not be [0, 0, 0]");
        const float degrees = r.number(rot["degrees"], child(p, "degrees"));
        m = rotation(axis, glm::radians(degrees)) * m;
    }
    if (o.contains("translate")) m = glm::translate(glm::mat4(1.0f), r.vec3(o["translate"], child(path, "translate"))) * m;
    for (int c = 0; c < 4; ++c)
        if (!finite3(glm::vec3(m[c])) || !std::isfinite(m[c][3])) failAt(r.file, path, "the transform is not finite");

    SceneGeometry out;
    if (o.contains("splishsplash")) {
        const std::string name = r.string(o["splishsplash"], child(path, "splishsplash"));
        const fs::path file = resolve(baseDir, name);
        if (lower(file.extension().string()) != ".json")
            failAt(r.file, child(path, "splishsplash"), "expected a SPlisHSPlasH scene file (.json), got " + name);
        out = readGeometryFile(file, nesting + 1, true);
    } else if (o.contains("file")) {
        const std::string name = r.string(o["file"], child(path, "file"));
        const fs::path file = resolve(baseDir, name);
        if (lower(file.extension().string()) == ".json") out = readGeometryFile(file, nesting + 1);
        else out.objects.push_back(checkedMesh(readGeometryMesh(file)));
    } else {
        GeometryObject g;
        if (o.contains("box")) {
            const std::string p = child(path, "box");
            const json& b = r.object(o["box"], p);
            r.onlyKeys(b, p, {"min", "max"});
            if (!b.contains("min") || !b.contains("max")) failAt(r.file, p, "needs \"min\" and \"max\"");
            const glm::vec3 lo = r.vec3(b["min"], child(p, "min")), hi = r.vec3(b["max"], child(p, "max"));
            for (int i = 0; i < 3; ++i)
                if (!(hi[i] > lo[i])) failAt(r.file, element(child(p, "max"), std::size_t(i)), "must exceed min's, " + num(lo[i]));
            g.name = "box";
            g.mesh = makeBoxMesh(lo, hi);
        } else if (o.contains("sphere")) {
            const std::string p = child(path, "sphere");
            const json& s = r.object(o["sphere"], p);
            r.onlyKeys(s, p, {"center", "radius"});
            if (!s.contains("radius")) failAt(r.file, p, "needs \"radius\"");
            const glm::vec3 c = s.contains("center") ? r.vec3(s["center"], child(p, "center")) : glm::vec3(0.0f);
            const float radius = r.number(s["radius"], child(p, "radius"));
            if (!(radius > 0.0f)) failAt(r.file, child(p, "radius"), "must be > 0 metres, got " + num(radius));
            g.name = "sphere";
            g.mesh = makeSphereMesh(c, radius);
        } else {
            const std::string p = child(path, "plane");
            const json& pl = r.object(o["plane"], p);
            r.onlyKeys(pl, p, {"point", "normal", "size"});
            const glm::vec3 point = pl.contains("point") ? r.vec3(pl["point"], child(p, "point")) : glm::vec3(0.0f);
            const glm::vec3 normal = pl.contains("normal") ? r.vec3(pl["normal"], child(p, "normal")) : glm::vec3(0, 1, 0);
            if (!(glm::dot(normal, normal) > 0.0f)) failAt(r.file, child(p, "normal"), "must not be [0, 0, 0]");
            float size = 10.0f;  // the side, metres
            if (pl.contains("size")) {
                size = r.number(pl["size"], child(p, "size"));
                if (!(size > 0.0f)) failAt(r.file, child(p, "size"), "must be > 0 metres, got " + num(size));
            }
            g.name = "plane";
            g.mesh = makePlaneMesh(point, normal, 0.5f * size);
        }
        out.objects.push_back(std::move(g));
    }

    // Keys that apply to every object this entry made (a SPlisHSPlasH scene
    // or a list file may make several).
    const bool identity = m == glm::mat4(1.0f);
    for (GeometryObject& g : out.objects) {
        if (!identity) {
            transformMesh(g.mesh, m);
            for (const glm::vec3& p : g.mesh.positions)
                if (!finite3(p)) failAt(r.file, path, "the transform moves a vertex of " + g.name + " out of float range");
        }
        if (o.contains("material")) applyMaterial(r, o["material"], child(path, "material"), g.material);
        if (o.contains("visible")) g.visible = r.boolean(o["visible"], child(path, "visible"));
        if (o.contains("cutaway")) g.cutaway = r.boolean(o["cutaway"], child(path, "cutaway"));
    }
    if (o.contains("name")) {
        const std::string name = r.string(o["name"], child(path, "name"));
        for (std::size_t i = 0; i < out.objects.size(); ++i)
            out.objects[i].name = out.objects.size() == 1 ? name : name + "[" + std::to_string(i) + "]";
    }
    return out;
}

SceneGeometry parseList(const json& root, const std::string& source, const fs::path& baseDir, int nesting) {
    const Reader r{source};
    SceneGeometry out;
    if (root.is_array()) {
        for (std::size_t i = 0; i < root.size(); ++i) out.append(parseObject(r, root[i], element("", i), baseDir, nesting));
    } else if (root.is_object()) {
        out = parseObject(r, root, "", baseDir, nesting);
    } else {
        failAt(source, "", "expected a geometry object {...} or a list of them [...], got " + r.typeOf(root));
    }
    return out;
}

bool isSplishSplash(const json& root) {
    return root.is_object() && (root.contains("RigidBodies") || root.contains("Boundaries"));
}

// SPlisHSPlasH's scene format (its documentation, file_format.md, and
// SceneParameterObjects.cpp's BoundaryParameterObject): "RigidBodies" (and,
// in older versions, "Boundaries") list bodies by "geometryFile" (OBJ/PLY,
// relative to the scene file's folder), "translation", "rotationAxis",
// "rotationAngle" (radians), "scale" [3], "isDynamic", "isWall" ("walls are
// typically not rendered", SPlisHSPlasH says: the tank), "mapInvert" (the
// inside is the outside: a container) and "color" (RGBA, since 2.8). Other
// keys (the sampling, the density maps) do not change what is drawn and are
// ignored. The mesh is scaled, rotated, then translated (x' = R (S x) + t).
SceneGeometry readSplishSplash(const json& root, const std::string& file, const fs::path& folder) {
    const Reader r{file};
    SceneGeometry out;
    for (const char* list : {"RigidBodies", "Boundaries"}) {
        if (!root.contains(list)) continue;
        const json& bodies = root[list];
        if (!bodies.is_array()) failAt(file, list, "expected a list [...], got " + r.typeOf(bodies));
        for (std::size_t i = 0; i < bodies.size(); ++i) {
            const std::string path = element(list, i);
            const json& b = r.object(bodies[i], path);
            if (!b.contains("geometryFile"))
                failAt(file, path, "no \"geometryFile\" (a body given only by its particles is not drawn)");
            const std::string geometry = r.string(b["geometryFile"], child(path, "geometryFile"));
            const glm::vec3 t = b.contains("translation") ? r.vec3(b["translation"], child(path, "translation")) : glm::vec3(0.0f);
            const glm::vec3 s = b.contains("scale") ? r.vec3(b["scale"], child(path, "scale")) : glm::vec3(1.0f);
            for (int k = 0; k < 3; ++k)
                if (s[k] == 0.0f) failAt(file, element(child(path, "scale"), std::size_t(k)), "must not be 0");
            glm::vec3 axis(1.0f, 0.0f, 0.0f);  // SPlisHSPlasH's default axis
            if (b.contains("rotationAxis")) axis = r.vec3(b["rotationAxis"], child(path, "rotationAxis"));
            const float angle = b.contains("rotationAngle") ? r.number(b["rotationAngle"], child(path, "rotationAngle")) : 0.0f;
            if (angle != 0.0f && !(glm::dot(axis, axis) > 0.0f))
                failAt(file, child(path, "rotationAxis"), "must not be [0, 0, 0] when rotationAngle is not 0");
            // SPlisHSPlasH writes its flags as JSON booleans; 0 and 1 are taken too.
            auto flag = [&](const char* key) {
                if (!b.contains(key)) return false;
                const json& v = b[key];
                if (v.is_number()) return r.number(v, child(path, key)) != 0.0f;
                return r.boolean(v, child(path, key));
            };
            GeometryObject g = checkedMesh(readGeometryMesh(resolve(folder, geometry)));
            transformMesh(g.mesh, glm::translate(glm::mat4(1.0f), t) * rotation(axis, angle) *
                                      glm::scale(glm::mat4(1.0f), s));
            for (const glm::vec3& p : g.mesh.positions)
                if (!finite3(p)) failAt(file, path, "the transform moves a vertex out of float range");
            g.cutaway = flag("isWall") || flag("mapInvert");
            (void)flag("isDynamic");  // drawn where it starts: the reader has no motion
            if (b.contains("color")) {
                const std::string p = child(path, "color");
                const json& c = b["color"];
                if (!c.is_array() || (c.size() != 3 && c.size() != 4))
                    failAt(file, p, "expected [r, g, b, a] or [r, g, b], got " + r.typeOf(c));
                // SPlisHSPlasH's viewer puts these numbers on the screen as
                // they are (no sRGB framebuffer), so they are the sRGB colour
                // seen there: decoded to linear here.
                glm::vec3 color;
                for (int k = 0; k < 3; ++k) color[k] = srgbToLinear(r.number(c[std::size_t(k)], element(p, std::size_t(k))));
                // An obstacle keeps its colour; a wall (a tank, usually the
                // same saturated blue as the water in SPlisHSPlasH's scenes)
                // keeps the neutral default, so the liquid reads against it.
                if (!g.cutaway) g.material.baseColor = color;
            }
            out.objects.push_back(std::move(g));
        }
    }
    if (out.empty()) failAt(file, "", "a SPlisHSPlasH scene with no rigid bodies or boundaries to draw");
    return out;
}

SceneGeometry readGeometryFile(const fs::path& path, int nesting, bool splishSplashOnly) {
    const std::string name = path.string();
    if (nesting > kMaxFileNesting)
        failAt(name, "", "geometry files name each other more than " + std::to_string(kMaxFileNesting) +
                           " deep (does one name itself?)");
    if (lower(path.extension().string()) != ".json") {
        SceneGeometry g;
        g.objects.push_back(checkedMesh(readGeometryMesh(path)));
        return g;
    }
    auto text = readJsonText(path, json_limits::kGeometry);
    if (!text) throw Failure{text.error().file, text.error().message, text.error().usage};
    const json root = parseJson(text.value(), name);
    if (isSplishSplash(root)) return readSplishSplash(root, name, path.parent_path());
    if (splishSplashOnly) failAt(name, "", "not a SPlisHSPlasH scene (no \"RigidBodies\" or \"Boundaries\")");
    return parseList(root, name, path.parent_path(), nesting);
}

template <class F>
Result<SceneGeometry> guarded(const std::string& source, F&& f) {
    try {
        return f();
    } catch (const Failure& e) {
        return Error{e.file, e.message, e.usage};
    } catch (const std::bad_alloc&) {
        return makeError(source, "ran out of memory while reading geometry");
    } catch (const std::exception& e) {
        return makeError(source, std::string("cannot be read: ") + e.what());
    } catch (...) {
        return makeError(source, "cannot be read (an unexpected error)");
    }
}

}  // namespace

Result<SceneGeometry> parseGeometry(std::string_view jsonText, const std::string& source, const fs::path& baseDir) {
    return guarded(source, [&] { return parseList(parseJson(jsonText, source), source, baseDir, 0); });
}

Result<SceneGeometry> parseSplishSplashScene(std::string_view jsonText, const std::string& source,
                                             const fs::path& baseDir) {
    return guarded(source, [&] {
        const json root = parseJson(jsonText, source);
        if (!isSplishSplash(root)) failAt(source, "", "not a SPlisHSPlasH scene (no \"RigidBodies\" or \"Boundaries\")");
        return readSplishSplash(root, source, baseDir);
    });
}

bool isInlineGeometry(std::string_view spec) {
    const std::size_t first = spec.find_first_not_of(" \t\r\n");
    return first != std::string_view::npos && (spec[first] == '{' || spec[first] == '[');
}

Result<SceneGeometry> readGeometry(const std::string& spec, const fs::path& baseDir) {
    if (spec.find_first_not_of(" \t\r\n") == std::string::npos)
        return makeError("", "no geometry given (an empty file name)");
    if (isInlineGeometry(spec)) return parseGeometry(spec, "inline geometry", baseDir);
    const fs::path path = resolve(baseDir, spec);
    return guarded(path.string(), [&] { return readGeometryFile(path, 0); });
}

}  // namespace meniscus
