// A GPU image: a shader storage buffer of width x height x channels floats in
// the CPU Image layout (row-major, row 0 = the TOP row, channels interleaved),
// so shaders index pixel (x, y) channel c as data[(y * W + x) * C + c] and a
// download is a plain copy into Image<float>, Image<glm::vec3> or Image<glm::vec4>.
#pragma once

#include <glm/glm.hpp>

#include "gl/objects.h"
#include "meniscus/types.h"

namespace meniscus::gl {

struct GpuImage {
    Buffer buffer;
    int width = 0, height = 0, channels = 1;

    std::size_t floats() const { return std::size_t(width) * std::size_t(height) * std::size_t(channels); }
    GLsizeiptr bytes() const { return GLsizeiptr(floats() * sizeof(float)); }
    // Whether it holds a w x h x c image (allocated): what a stage checks its inputs with.
    bool sized(int w, int h, int c) const { return width == w && height == h && channels == c && buffer.id() != 0; }

    // Sets the shape and makes sure the storage holds it (contents undefined
    // after growing; the buffer is never shrunk).
    void resize(int w, int h, int c) {
        width = w;
        height = h;
        channels = c;
        buffer.reserve(std::max<GLsizeiptr>(bytes(), 4));  // an empty buffer cannot be bound
    }
    // Binds exactly this image's bytes to shader storage binding point `binding`.
    void bind(GLuint binding) const {
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, binding, buffer.id(), 0, std::max<GLsizeiptr>(bytes(), 4));
    }

    // Becomes a GPU-side copy of `src` (shape and pixels).
    void copyFrom(const GpuImage& src) {
        resize(src.width, src.height, src.channels);
        buffer.copyFrom(src.buffer, src.bytes());
    }

    template <class T>
    void upload(const Image<T>& img) {
        static_assert(sizeof(T) % sizeof(float) == 0, "float pixels");
        resize(img.width, img.height, int(sizeof(T) / sizeof(float)));
        if (!img.empty()) buffer.upload(img.pixels.data(), bytes());
    }
    // Reads back (waits for the GPU). T must have `channels` floats.
    template <class T>
    Image<T> download() const {
        Image<T> out(width, height);
        if (!out.empty() && sizeof(T) == std::size_t(channels) * sizeof(float))
            buffer.download(out.pixels.data(), bytes());
        return out;
    }
};

}  // namespace meniscus::gl
