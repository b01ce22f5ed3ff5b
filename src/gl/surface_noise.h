// GL surface noise (docs/pipeline.md#noise-and-foam): the GPU twin of
// cpu::splatNoise and cpu::bumpNormals, and of cpu::splatWhitening, the
// velocity whitening map (Cords & Staadt 2008, "Instant Liquids" §4), which
// splats the same sprites. Needs a current GL 4.3 context (gl::Context) on the
// calling thread and the frame's parameter block bound (gl::FrameParamsBlock).
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gl/fluid_segments.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the sprite programs and buffers of both payloads; reuse one across
// frames (buffers grow only when needed).
class SurfaceNoise {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<SurfaceNoise> create();

    // The GL twin of cpu::splatNoise + cpu::bumpNormals, bit for bit: `noise`
    // (resized to P.size, W x H x 1) gets N, 0 where `depth` has no fluid, and
    // `normals` (when W x H x 3) are bumped in place. The particles are
    // `count` world positions in `positions` (packed xyz floats: Splat's
    // buffer), idz and amplitude per particle as in cpu::splatNoise (missing
    // idz: 0; amplitude not of `count` values: all 1). `camera` is the frame's
    // (its near plane and focal length, exactly as the CPU reads them). A depth
    // of another size than P.size gives N = 0 and leaves the normals as they
    // are, as on the CPU. Asynchronous: nothing waits for the GPU here.
    void run(const FrameParams& frame, const Camera& camera, const NoiseParams& params, const Buffer& positions,
             GLuint count, std::span<const float> idz, std::span<const float> amplitude, const GpuImage& depth,
             GpuImage& normals, GpuImage& noise);

    // The GL twin of cpu::splatWhitening, bit for bit: `map` (resized to
    // P.size, W x H x 1) gets the weighted mean whiteness of the sprites of
    // params (amplitude 1) where `depth` has fluid, 0 elsewhere; whiteness[i]
    // is particle i's (missing: 0). Particles and camera as in run(); a depth
    // of another size than P.size gives 0 everywhere. Asynchronous.
    void runWhitening(const FrameParams& frame, const Camera& camera, const WhiteningParams& params,
                      const Buffer& positions, GLuint count, std::span<const float> whiteness, const GpuImage& depth,
                      GpuImage& map);

private:
    // The payload-specific uniforms of noise_splat.comp's passes.
    struct Scatter {
        bool whitening = false;
        float spriteM = 0.0f, falloffM = 0.0f, sigma = 0.0f;
        const NoiseParams* noise = nullptr;  // the octaves' parameters (noise only)
    };
    // The sums (planes x W*H uints) zeroed and the attributes (staging_)
    // uploaded, then noise_splat.comp's three passes over them.
    void scatter(const FrameParams& frame, const Camera& camera, const Buffer& positions, GLuint count,
                 const GpuImage& depth, GLuint planes, const Scatter& sc);
    // noise_resolve.comp over the fluid segments (built beforehand): N into
    // `out` and the normals bumped (when given), or the whitening map.
    void resolve(GpuImage* normals, GpuImage& out, bool whitening, float jump, float spriteF, float bump);

    Program splat_, resolve_;
    Buffer attributes_;       // per particle (idz or whiteness, amplitude)
    Buffer sums_;             // W*H fixed-point sums (the whitening's two: 2*W*H)
    Buffer lists_;            // noise_splat.comp's Lists block: passes 1 and 2's dispatches and sprites
    Texture depthTex_;        // R32F buffer texture over the depth
    Texture sumsTex_;         // R32I buffer texture over the sums
    Texture normalsTex_;      // R32F image buffer over the normals (bumped in place)
    Texture noiseTex_;        // R32F image buffer over N (or the whitening map)
    FluidSegments segments_;  // of the depth, for the resolve
    std::vector<glm::vec2> staging_;  // the attributes on their way up
};

}  // namespace meniscus::gl
