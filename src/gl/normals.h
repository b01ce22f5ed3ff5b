// GL normals stage (docs/pipeline.md#normals): the GPU twin of
// meniscus::cpu::computeNormals. Needs a current GL 4.3 context (gl::Context)
// on the calling thread.
#pragma once

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the normals program; reuse one across frames.
class Normals {
public:
    // Compiles the shader; an error carries the driver's log.
    static Result<Normals> create();

    // GL twin of cpu::computeNormals(depth, camera, P.radius, P.normalsJumpRadii):
    // view-space unit normals (+z toward the camera) where depth is finite,
    // (0,0,0) elsewhere; W x H x 3. Camera, radius and jump threshold from the
    // bound frame block (binding 0, uploaded by the caller from `frame`);
    // `depth` must be P.size (W x H x 1), else the normals are all (0,0,0).
    // Asynchronous: nothing waits for the GPU here.
    void run(const FrameParams& frame, const GpuImage& depth, GpuImage& normals);

private:
    Program program_;
    Texture depthTex_;  // R32F buffer texture over the depth
};

}  // namespace meniscus::gl
