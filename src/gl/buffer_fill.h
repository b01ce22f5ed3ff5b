// Buffer fills and copies by a compute shader (shaders/buffer_fill.comp)
// instead of the driver's glClearBufferSubData / glCopyBufferSubData, which
// NVIDIA's driver runs on a copy engine: on an H200 at 1920x1080 the splat's
// two clears took 0.6 ms and the normals' clear 0.8 ms, against 0.05 ms for
// the whole normals stage with a shader clear (docs/performance.md#gl-backend-on-a-gpu-nvidia-h200).
// On llvmpipe the driver's own fill is a memset, faster than a shader pass, so
// the backend picks per renderer (useShaderFills) and installs its programs
// for the calls it makes (ScopedBufferFill); Buffer::fill and copyFrom/
// copyRange use them when installed on the calling thread, the driver
// otherwise. Both give the same bits.
#pragma once

#include <string_view>

#include <epoxy/gl.h>

#include "gl/objects.h"
#include "meniscus/result.h"

namespace meniscus::gl {

class BufferFill {
public:
    static Result<BufferFill> create();
    // Sets `bytes` (a multiple of 4) of `dst` from `dstOffset` to the 32-bit pattern `bits`.
    void fill(GLuint dst, GLintptr dstOffset, GLsizeiptr bytes, GLuint bits) const;
    // Copies `bytes` (a multiple of 4) of `src` from `srcOffset` to `dst` at `dstOffset`.
    void copy(GLuint dst, GLintptr dstOffset, GLuint src, GLintptr srcOffset, GLsizeiptr bytes) const;

    // Writes into `dst` the W x H image `src` framed by `pad` words of `bits`
    // on every side: (W + 2 pad) x (H + 2 pad) words, row by row.
    void padCopy(GLuint dst, GLuint src, int W, int H, int pad, GLuint bits) const;
    // Whether the shader path takes a range: at least 64 KiB, whole words, and
    // offsets the storage-buffer binding accepts (the driver's call otherwise).
    bool takes(GLintptr dstOffset, GLintptr srcOffset, GLsizeiptr bytes) const;

private:
    void run(GLuint dst, GLintptr dstOffset, GLuint src, GLintptr srcOffset, GLsizeiptr bytes, GLuint bits,
             int mode, const int* padded) const;
    Program program_;
    GLintptr offsetAlignment_ = 256;  // GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT
};

// Whether a renderer (GL_RENDERER) is one of Mesa's software rasterisers
// (llvmpipe, softpipe, swrast), which the GL backend's work distribution was
// first tuned for; every other is a hardware GPU.
bool isSoftwareRenderer(std::string_view renderer);

// Whether a renderer gets shader fills: every hardware driver, not the
// software rasterisers. MENISCUS_GL_FILL=shader or =driver forces either
// (tests run the shader path on llvmpipe that way).
bool useShaderFills(std::string_view renderer);

// Installs `fill` (or nothing, when null) for the Buffer calls made on this
// thread while the guard lives; the previous one comes back after.
class ScopedBufferFill {
public:
    explicit ScopedBufferFill(const BufferFill* fill);
    ~ScopedBufferFill();
    ScopedBufferFill(const ScopedBufferFill&) = delete;
    ScopedBufferFill& operator=(const ScopedBufferFill&) = delete;

private:
    const BufferFill* previous_;
};

}  // namespace meniscus::gl
