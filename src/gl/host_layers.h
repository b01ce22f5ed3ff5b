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

}  // namespace meniscus::gl
