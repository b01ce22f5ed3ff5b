// The HDR environment map on the GPU (docs/pipeline.md#environment-map): the
// texels of shared::EnvironmentMap as a float storage buffer, which the scene,
// shading and geometry shaders read through src/shared/environment.h as
// `environmentTexels` (binding kEnvironmentBinding), with its size, rotation
// and intensity as two uniforms. Uploaded once while the map stays the same.
#pragma once

#include <memory>

#include <glm/glm.hpp>

#include "gl/gpu_image.h"
#include "meniscus/environment.h"
#include "shared/environment.h"

namespace meniscus::gl {

// The storage-buffer binding of `environmentTexels` in every shader that
// samples the map (free in scene.comp, shade.comp and geometry_shade.comp).
inline constexpr GLuint kEnvironmentBinding = 7;

struct EnvironmentGpu {
    GpuImage texels;  // 3 floats per texel; a dummy texel when there is no map
    shared::EnvironmentMap map;  // what the uniforms describe (texels null: the sky)
    // The image uploaded, kept alive so that no new map takes its address
    // (which is what update compares).
    std::shared_ptr<const EnvironmentImage> image;

    // Makes the buffer hold `m` (uploading only a new map).
    void update(const shared::EnvironmentMap& m, std::shared_ptr<const EnvironmentImage> keep) {
        const bool same = map.texels == m.texels && map.width == m.width && map.height == m.height &&
                          texels.buffer.id() != 0;
        if (!same) {
            if (m.enabled()) {
                texels.resize(m.width, m.height, 3);
                texels.buffer.upload(m.texels, texels.bytes());
            } else {
                texels.resize(1, 1, 3);  // bound but never read (uEnvSize.x is 0)
            }
        }
        map = m;
        image = std::move(keep);
    }
    // Binds the texels and sets the program's uniforms at `sizeLoc` (ivec2:
    // width, 0 without a map; height), `sizeLoc + 1` (vec2: rotation in
    // turns, intensity) and `irradianceLoc` (vec3[9], 9 locations: the
    // irradiance's coefficients). The program must be in use.
    void bind(GLint sizeLoc, GLint irradianceLoc) const {
        texels.bind(kEnvironmentBinding);
        glUniform2i(sizeLoc, map.enabled() ? map.width : 0, map.enabled() ? map.height : 1);
        glUniform2f(sizeLoc + 1, map.rotation, map.intensity);
        glUniform3fv(irradianceLoc, 9, &map.irradiance[0].x);
    }
};

// For a pass run without one (tests of a single pass): no map.
inline void bindNoEnvironment(GLint sizeLoc, GLint irradianceLoc) {
    glUniform2i(sizeLoc, 0, 1);
    glUniform2f(sizeLoc + 1, 0.0f, 1.0f);
    const glm::vec3 zero[9] = {};
    glUniform3fv(irradianceLoc, 9, &zero[0].x);
}

}  // namespace meniscus::gl
