// GL anisotropic kernels (docs/pipeline.md#anisotropic-kernels): the GPU twin
// of meniscus::computeAnisotropy (core/anisotropy.h), writing the splat's
// particle and shape buffers directly. Needs a current GL 4.3 context on the
// calling thread.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "core/anisotropy.h"
#include "gl/objects.h"
#include "meniscus/params.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the programs and the grid's buffers; reuse one across frames
// (buffers grow only when needed).
class Anisotropy {
public:
    static Result<Anisotropy> create();

    // GL twin of computeAnisotropy(positions, radius, params, out, radii):
    // uploads the positions (and the own radii, when one per position) and
    // runs the passes; `centres` gets the smoothed centres (packed xyz
    // floats) and `shapes` the ellipsoids as splat.comp's Shapes block reads
    // them (12 floats each: m's and q's upper triangles), every half-axis
    // times shapeScale (scaledShape; 1: as they are). Both are grown as
    // needed. Asynchronous: nothing is read back.
    void run(std::span<const glm::vec3> positions, float radius, const AnisotropyParams& params,
             std::span<const float> radii, float shapeScale, Buffer& centres, Buffer& shapes);
    // The same from `count` positions already in positionBuffer() (packed xyz
    // floats, written on the GPU: a host's own buffer gathered into it).
    void runOnDevice(GLuint count, float radius, const AnisotropyParams& params, std::span<const float> radii,
                     float shapeScale, Buffer& centres, Buffer& shapes);
    Buffer& positionBuffer() { return positions_; }

private:
    Program grid_, pca_;
    Buffer positions_, radii_, counts_, starts_, chunks_, unsorted_, sorted_, bucketOf_;
    Texture sortedTex_, startsTex_;  // anisotropy.comp reads sorted_ and starts_ as buffer textures
};

// One-shot convenience (tests): create, run, read the centres and shapes back.
Result<Ellipsoids> anisotropyOnGpu(std::span<const glm::vec3> positions, float radius,
                                   const AnisotropyParams& params, std::span<const float> radii = {});

}  // namespace meniscus::gl
