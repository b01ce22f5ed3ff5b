// The per-frame parameter block (src/shared/frame_params.h) on the C++ side:
// packed from the same settings the CPU backend reads and uploaded once per
// frame as the std140 uniform block at binding 0.
#pragma once

#include "gl/objects.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "shared/frame_params.h"

namespace meniscus::gl {

using shared::FrameParams;

// Every field from the camera, radius and stage parameters (filter: the
// active variant's fields, the others 0).
FrameParams packFrameParams(const Camera& camera, float radius, const FilterParams& filter,
                            const ThicknessParams& thickness, const ShadingParams& shading);

// The uniform buffer holding one FrameParams.
class FrameParamsBlock {
public:
    static constexpr GLuint kBinding = 0;  // layout(std140, binding = 0) in frame_params.h
    // Uploads `p` and binds it at kBinding.
    void upload(const FrameParams& p) {
        buffer_.upload(&p, GLsizeiptr(sizeof p));
        bind();
    }
    void bind() const { glBindBufferBase(GL_UNIFORM_BUFFER, kBinding, buffer_.id()); }

private:
    Buffer buffer_;
};

}  // namespace meniscus::gl
