// What of the scene geometry (include/meniscus/geometry.h) a frame draws, said
// once for both backends' geometry and glass stages (src/cpu/geometry.cpp,
// src/gl/geometry.cpp): the visible objects, and of each which faces.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/geometry.h"

namespace meniscus {

// Whether the frame draws `object` at all: visible, with triangles.
bool drawsObject(const GeometryObject& object);
// Whether the geometry has a drawn object at all (the geometry stage, the
// shadows' default), and a drawn glass object (the glass stage's fronts).
bool drawsAnyObject(const SceneGeometry* geometry);
bool drawsGlass(const SceneGeometry* geometry);

// Which triangles of a mesh are drawn, by the side of their plane the eye is
// on (a triangle wound counter-clockwise seen from outside, its outside
// being the side its normal cross(b - a, c - a) points to).
enum class Faces {
    All,
    Back,   // those whose outside faces away from the eye (the far walls' insides)
    Front,  // those whose outside faces the eye
};

// The triangles of `mesh` seen from `eye` that `faces` keeps: the mesh itself
// for Faces::All, else a copy in *scratch with the same vertices and only the
// kept triangles. Exact and on the host: the same triangles on both backends.
const TriangleMesh& facesSeenFrom(const TriangleMesh& mesh, const glm::vec3& eye, Faces faces, TriangleMesh* scratch);
// The same as triangle indices into `mesh`'s own vertices (nothing copied but
// the kept indices, into *scratch; the mesh's own for Faces::All).
std::span<const std::uint32_t> facesSeenFrom(const TriangleMesh& mesh, const glm::vec3& eye, Faces faces,
                                             std::vector<std::uint32_t>* scratch);

// The base colour map `object` is drawn with, or null: an opaque object whose
// material has a whole texture (3 W H texels) and whose mesh has one texture
// coordinate per vertex.
const GeometryTexture* drawnTexture(const GeometryObject& object);

// The faces the scene layer draws of `object`: of a cut-away container
// (GeometryObject::cutaway) and of glass only the back faces (a tank seen
// from outside loses the walls between the camera and the liquid, and its
// lid seen from above, as ParaView users clip them; glass's front faces are
// drawn over the liquid by the glass stage); of anything else all.
Faces sceneFaces(const GeometryObject& object);

}  // namespace meniscus
