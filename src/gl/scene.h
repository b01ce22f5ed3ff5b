// GL scene stage (docs/pipeline.md#scene): the GPU twin of meniscus::cpu::castScene.
// Needs a current GL 4.3 context (gl::Context) on the calling thread.
#pragma once

#include "gl/environment.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/result.h"
#include "shared/studio.h"

namespace meniscus::gl {

// Owns the scene program; reuse one across frames.
class SceneCaster {
public:
    // Compiles the shader; an error carries the driver's log.
    static Result<SceneCaster> create();

    // GL twin of cpu::castScene: color (W x H x 4, linear RGBA) and depth
    // (W x H x 1, +inf = sky) for the camera in the bound frame block (binding
    // 0, uploaded by the caller from `frame`); the studio geometry goes in as
    // plain uniforms, lit (and its sky's sun placed) from studio.lightDirWorld.
    // A disabled studio gives (0,0,0,0) and +inf everywhere.
    // Asynchronous: nothing waits for the GPU here.
    // environment: the HDR map instead of the sky (null or disabled: the sky).
    void run(const FrameParams& frame, const shared::Studio& studio, GpuImage& color, GpuImage& depth,
             const EnvironmentGpu* environment = nullptr);

private:
    Program program_;
};

}  // namespace meniscus::gl
