// The embedding's scene layer (Renderer::drawIntoHost, docs/compositing.md):
// a host application's colour and depth textures turned into the scene
// stage's two images, as core/backdrop_layer.h turns a backdrop from files on
// the host. Needs the host's GL context current on the calling thread.
#pragma once

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/camera.h"
#include "meniscus/renderer.h"
#include "meniscus/result.h"

namespace meniscus::gl {

class HostLayerImport {
public:
    // Compiles the shader and uploads the 8-bit sRGB decoding table
    // (shared::srgbDecodeTable, the CPU's own); an error carries the driver's log.
    static Result<HostLayerImport> create();

    // color (W x H x 4, linear RGBA, row 0 = top) and depth (W x H x 1, eye
    // depth in metres, +inf: nothing) of the host's textures (row 0 = bottom),
    // for `camera` (the host's, cameraFromGlMatrices): the colour decoded from
    // 8-bit sRGB codes when host.colorIsSrgb (by the CPU's table, so a code
    // gives the CPU's bits), alpha 1; the window depth through
    // shared::backdropEyeDepth with the camera's near and far planes, as a
    // backdrop of kind window:NEAR,FAR is read. Asynchronous.
    void run(const HostLayers& host, const Camera& camera, GpuImage& color, GpuImage& depth);

private:
    Program program_;
    Buffer decode_;  // 256 floats: shared::srgbDecodeTable
    // Nearest texels, no depth comparison: bound over the host's textures'
    // own sampling state (which it keeps), so a texture without mipmaps and
    // a minifying filter that wants them still reads, and a shadow-map depth
    // texture gives its depth.
    Sampler sampler_;
};

// The particles of a host's own GL buffer (HostParticleBuffer) copied on the
// GPU into a packed xyz buffer of the renderer's, whatever the host's offset
// and stride: nothing crosses to the CPU.
class HostParticleGather {
public:
    static Result<HostParticleGather> create();

    // An error naming what is wrong when `particles` cannot be read as
    // described: no such buffer, an offset or stride not a multiple of 4, a
    // stride under 12 bytes, positions past the buffer's end (its
    // GL_BUFFER_SIZE), or more words than 32-bit indices reach.
    static Status check(const HostParticleBuffer& particles);

    // `target` grown to the particles' packed positions and filled from the
    // host's buffer (checked). Asynchronous.
    void run(const HostParticleBuffer& particles, Buffer& target);

private:
    Program program_;
};

}  // namespace meniscus::gl
