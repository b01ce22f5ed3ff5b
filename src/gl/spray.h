// GL spray drops (docs/pipeline.md#classification,
// docs/pipeline.md#noise-and-foam): the GPU twin of cpu::drawSpray, the
// particles classified as spray drawn as small lit, semi-transparent drops
// stretched along their velocity, composited with depth over the shaded image.
// Needs a current GL 4.3 context (gl::Context) on the calling thread.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/result.h"
#include "shared/environment.h"

namespace meniscus::gl {

// Owns the drop programs and buffers; reuse one across frames (buffers grow
// only when needed).
class SprayDrops {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<SprayDrops> create();

    // The GL twin of cpu::drawSpray, bit for bit: the drops (world positions
    // and velocities, m/s; velocities may be empty: round drops) laid over
    // `color` (W x H x 4, the camera's size) in place, each hidden where the
    // fluid's `depth` or the `sceneDepth` (when given and camera-sized) is
    // nearer than its centre, lit by lightDirWorld and the ambient (with an
    // HDR `environment`, its irradiance: shared::sprayLight, computed on the
    // host as the CPU's); `cover` (resized to
    // W x H x 1) gets their cover per pixel, 0 where none. A depth or colour
    // of another size leaves the colour as it is and the cover 0, as on the
    // CPU. The drops are projected on the host (the CPU's code, so the same
    // floats), the pixels on the GPU. Asynchronous: nothing waits for the GPU here.
    void run(const Camera& camera, std::span<const glm::vec3> positionsWorld,
             std::span<const glm::vec3> velocitiesWorld, float radius, const SprayParams& params,
             const glm::vec3& lightDirWorld, const GpuImage& depth, const GpuImage* sceneDepth, GpuImage& color,
             GpuImage& cover, const shared::EnvironmentMap& environment = {});

    // The last run()'s drops with pixels on screen, and the work items they
    // were cut into (spray_splat.comp's invocations). For the tests.
    GLuint drawnDrops() const { return drawn_; }
    GLuint chunks() const { return chunks_; }

    // A drop as spray_splat.comp reads it: shared::SprayDrop in std430 layout
    // (its ivec4 at byte 32).
    struct alignas(16) Packed {
        glm::vec2 a, b;
        float radiusPx, z, tau, pad;
        glm::ivec4 rect;
    };

private:
    Program splat_, resolve_;
    Buffer drops_;        // the drops with pixels on screen
    Buffer chunkList_;    // the work items: (drop, first pixel of its rectangle)
    Buffer sums_;         // W*H fixed-point optical depths
    Texture depthTex_;    // R32F buffer texture over the fluid depth
    Texture sceneTex_;    // R32F buffer texture over the scene depth
    Texture sumsTex_;     // R32I buffer texture over the sums
    Texture colorTex_;    // RGBA32F image buffer over the colour (composited in place)
    Texture coverTex_;    // R32F image buffer over the cover
    Buffer dummy_;        // bound in place of a missing scene depth (never read)
    std::vector<Packed> staging_;     // the drops on their way up
    std::vector<glm::uvec2> items_;   // the work items on their way up
    GLuint drawn_ = 0, chunks_ = 0;
};

}  // namespace meniscus::gl
