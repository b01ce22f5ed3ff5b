// GL raycast stage (docs/pipeline.md#ray-cast-surface): the GPU twin of
// meniscus::cpu::raycastSurface. Needs a current GL 4.3 context on the calling
// thread.
#pragma once

#include "core/sph_field.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/params.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the program and the field's buffers; reuse one across frames.
class Raycast {
public:
    static Result<Raycast> create();

    // GL twin of cpu::raycastSurface(camera, field, params, P.radius, start,
    // sceneDepth): uploads the field's grid, then writes the iso-surface's eye
    // depth (+inf: none) and view-space normals ((0,0,0): none), P.size each.
    // `field` null: no surface. Asynchronous.
    void run(const FrameParams& frame, const SphField* field, const RaycastParams& params, const GpuImage& start,
             const GpuImage* sceneDepth, GpuImage& depth, GpuImage& normals);

private:
    Program program_;
    Buffer points_, starts_, quiet_;
    std::vector<glm::vec4> packed_;  // the grid's points as vec4 (std430), kept across frames
};

}  // namespace meniscus::gl
