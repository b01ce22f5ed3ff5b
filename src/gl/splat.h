// GL depth splat (SPEC §3.3): the GPU twin of meniscus::cpu::splatDepth.
// Needs a current GL 4.3 context (gl::Context) on the calling thread.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "gl/objects.h"
#include "meniscus/camera.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::gl {

// Owns the splat's programs and GPU buffers; reuse one across frames (buffers
// grow only when needed).
class DepthSplat {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<DepthSplat> create();

    // Uploads the particles (world positions, metres) for the next run().
    void uploadParticles(std::span<const glm::vec3> positionsWorld);

    // depthBuffer() = camera.width x camera.height float bits (row-major, row 0
    // = top): per pixel the nearest-hit eye depth over the uploaded spheres,
    // +inf where none; hits nearer than camera.nearM or at/behind sceneDepth
    // (when given, camera-sized) are discarded -- exactly cpu::splatDepth.
    // Asynchronous: nothing waits for the GPU here.
    void run(const Camera& camera, float radius, const Image<float>* sceneDepth = nullptr);

    // The last run's depth, read back (waits for the GPU).
    Image<float> readDepth() const;
    const Buffer& depthBuffer() const { return depth_; }

private:
    Program splat_, resolve_;
    Buffer positions_, depth_, scene_;
    GLuint count_ = 0;
    int width_ = 0, height_ = 0;
};

// One-shot convenience: create, upload, run, read back.
Result<Image<float>> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                const Image<float>* sceneDepth = nullptr);

}  // namespace meniscus::gl
