// GL depth splat and thickness chords (docs/pipeline.md#depth-splat,
// docs/pipeline.md#thickness): the GPU twin of cpu::splatBins. Needs a current
// GL 4.3 context (gl::Context) on the calling thread and the frame's parameter
// block bound (gl::FrameParamsBlock).
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/anisotropy.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/camera.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::gl {

// Owns the splat's programs and the particle buffer; reuse one across frames
// (buffers grow only when needed).
class Splat {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<Splat> create();

    // Uploads the particles (world positions, metres) for the next run(),
    // and with `shapes` (one per position) their ellipsoids (anisotropic
    // kernels): run() then splats those instead of spheres of frame.radius.
    void uploadParticles(std::span<const glm::vec3> positionsWorld, std::span<const EllipsoidShape> shapes = {});
    // The particles and their ellipsoids written on the GPU instead
    // (gl/anisotropy.h: the smoothed centres into particleBuffer(), the
    // shapes into shapeBuffer(), splat.comp's layouts): run() then splats
    // `count` ellipsoids from those buffers, nothing uploaded.
    Buffer& particleBuffer() { return positions_; }
    Buffer& shapeBuffer() { return shapes_; }
    void useDeviceShapes(GLuint count) {
        count_ = count;
        ellipsoids_ = true;
    }
    // `count` positions written into particleBuffer() on the GPU (a host's
    // own buffer gathered), splatted as spheres of frame.radius.
    void useDeviceParticles(GLuint count) {
        count_ = count;
        ellipsoids_ = false;
    }
    // The uploaded positions (packed xyz floats) and their count, for the
    // stages that read them too (the surface noise): uploaded once per frame.
    const Buffer& particleBuffer() const { return positions_; }
    GLuint particleCount() const { return count_; }

    // depth (resized to the camera of `frame`): per pixel the nearest-hit eye
    // depth over the uploaded spheres, +inf where none; hits nearer than the
    // near plane or at/behind sceneDepth (when given, camera-sized) are
    // discarded -- exactly cpu::splatDepth. thickness (when given): the summed
    // chords clipped to [near, scene) in fixed point, resolved to metres times
    // frame.thicknessWeight, unblurred -- cpu::splatBins' chords, by the same
    // formulas (shared/splat_chords.h), resolved as cpu::resolveThickness
    // does. Asynchronous: nothing waits for the GPU here.
    void run(const FrameParams& frame, const GpuImage* sceneDepth, GpuImage& depth, GpuImage* thickness);

    // The chords alone on the grid of one pixel per divisor x divisor block
    // (2 or 4), rays through the block centres; `sceneDepth` (when given) is
    // on that grid, each block's nearest scene depth. `thickness` is resized to
    // ceil(W / divisor) x ceil(H / divisor) -- cpu::splatChordsLowRes, unblurred.
    // With resolve false, `thickness` keeps the fixed-point sums (uints).
    void runChordsLowRes(const FrameParams& frame, const GpuImage* sceneDepth, int divisor, GpuImage& thickness,
                         bool resolve = true);

    // Sort-last (meniscus/sort_last.h): run() with the chords left as the
    // fixed-point sums (one uint per pixel) -- cpu::splatPartial's at full
    // resolution; and the resolve alone, in place: sums (of any grid) into
    // metres times frame.thicknessWeight (shared/splat_chords.h).
    void runPartial(const FrameParams& frame, const GpuImage* sceneDepth, GpuImage& depth, GpuImage& chords);
    void resolveChords(const FrameParams& frame, GpuImage& chords);

private:
    void runAt(const FrameParams& frame, const GpuImage* sceneDepth, GpuImage* depth, GpuImage* thickness,
               int divisor, bool resolve);

    Program splat_, resolve_;
    Buffer positions_, noScene_;
    Buffer shapes_;  // splat.comp's Shapes block: 12 floats per particle
    std::vector<float> packedShapes_;  // its host copy, packed
    bool ellipsoids_ = false;
    Texture sceneTex_;  // R32F buffer texture over the scene depth (or noScene_)
    Texture depthTex_;  // R32F buffer texture over the depth being splatted
    Buffer big_;  // splat.comp's Big block: pass 1's indirect dispatch and the large spheres
    GLuint count_ = 0;
};

// One-shot convenience (tests): create, upload, run, read back the depth.
Result<Image<float>> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                const Image<float>* sceneDepth = nullptr, std::span<const EllipsoidShape> shapes = {});

}  // namespace meniscus::gl
