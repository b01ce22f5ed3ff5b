// Small RAII owners of GL objects (GL backend only; needs a current context for
// creation and destruction). Move-only; a default-constructed one owns nothing.
#pragma once

#include <string>
#include <string_view>
#include <utility>

#include <epoxy/gl.h>

#include "meniscus/result.h"

namespace meniscus::gl {

// One GL name, released with Deleter::release(name) when non-zero.
template <class Deleter>
class Handle {
public:
    Handle() = default;
    explicit Handle(GLuint id) : id_(id) {}
    ~Handle() { reset(); }
    Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, 0);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset() {
        if (id_) Deleter::release(id_);
        id_ = 0;
    }

private:
    GLuint id_ = 0;
};

namespace detail {
struct BufferDeleter { static void release(GLuint id) { glDeleteBuffers(1, &id); } };
struct TextureDeleter { static void release(GLuint id) { glDeleteTextures(1, &id); } };
struct FramebufferDeleter { static void release(GLuint id) { glDeleteFramebuffers(1, &id); } };
struct QueryDeleter { static void release(GLuint id) { glDeleteQueries(1, &id); } };
struct VertexArrayDeleter { static void release(GLuint id) { glDeleteVertexArrays(1, &id); } };
struct ShaderDeleter { static void release(GLuint id) { glDeleteShader(id); } };
struct ProgramDeleter { static void release(GLuint id) { glDeleteProgram(id); } };
struct SamplerDeleter { static void release(GLuint id) { glDeleteSamplers(1, &id); } };
}  // namespace detail

using Texture = Handle<detail::TextureDeleter>;
using Framebuffer = Handle<detail::FramebufferDeleter>;
using Query = Handle<detail::QueryDeleter>;
using VertexArray = Handle<detail::VertexArrayDeleter>;
using Shader = Handle<detail::ShaderDeleter>;
using Program = Handle<detail::ProgramDeleter>;
using Sampler = Handle<detail::SamplerDeleter>;

inline Texture makeTexture() { GLuint id = 0; glGenTextures(1, &id); return Texture(id); }
inline Framebuffer makeFramebuffer() { GLuint id = 0; glGenFramebuffers(1, &id); return Framebuffer(id); }
inline Query makeQuery() { GLuint id = 0; glGenQueries(1, &id); return Query(id); }
inline VertexArray makeVertexArray() { GLuint id = 0; glGenVertexArrays(1, &id); return VertexArray(id); }
inline Sampler makeSampler() { GLuint id = 0; glGenSamplers(1, &id); return Sampler(id); }

namespace detail {
// The shader path of gl/buffer_fill.h: false (nothing done) when no BufferFill
// is installed on this thread, and the driver's call is made instead.
bool shaderFill(GLuint dst, GLintptr dstOffset, GLsizeiptr bytes, GLuint bits);
bool shaderCopy(GLuint dst, GLintptr dstOffset, GLuint src, GLintptr srcOffset, GLsizeiptr bytes);
bool shaderPadCopy(GLuint dst, GLuint src, int W, int H, int pad, GLuint bits);
}  // namespace detail

// A buffer object that remembers its size in bytes; resize() only reallocates
// when it must grow, so per-frame reuse does not churn the driver.
class Buffer {
public:
    Buffer() = default;
    GLuint id() const { return h_.id(); }
    GLsizeiptr size() const { return size_; }

    // Ensures at least `bytes` of storage (contents undefined after growing).
    void reserve(GLsizeiptr bytes, GLenum usage = GL_DYNAMIC_DRAW) {
        if (!h_) {
            GLuint id = 0;
            glGenBuffers(1, &id);
            h_ = Handle<detail::BufferDeleter>(id);
        }
        if (bytes <= size_) return;
        glBindBuffer(GL_COPY_WRITE_BUFFER, h_.id());
        glBufferData(GL_COPY_WRITE_BUFFER, bytes, nullptr, usage);
        size_ = bytes;
    }
    // Ensures the size and uploads `bytes` from `data` at offset 0.
    void upload(const void* data, GLsizeiptr bytes, GLenum usage = GL_DYNAMIC_DRAW) {
        reserve(bytes, usage);
        if (bytes == 0) return;
        glBindBuffer(GL_COPY_WRITE_BUFFER, h_.id());
        glBufferSubData(GL_COPY_WRITE_BUFFER, 0, bytes, data);
    }
    // Sets the first `bytes` (a multiple of 4) to the 32-bit pattern `bits`:
    // the driver's fill, a memset on llvmpipe (+inf floats = 0x7f800000).
    void fill(GLsizeiptr bytes, GLuint bits) const {
        if (bytes <= 0 || detail::shaderFill(h_.id(), 0, bytes, bits)) return;
        glBindBuffer(GL_COPY_WRITE_BUFFER, h_.id());
        glClearBufferSubData(GL_COPY_WRITE_BUFFER, GL_R32UI, 0, bytes, GL_RED_INTEGER, GL_UNSIGNED_INT, &bits);
    }
    // Copies the first `bytes` of `src` to the start of this buffer, on the GPU.
    void copyFrom(const Buffer& src, GLsizeiptr bytes) const {
        if (bytes <= 0 || detail::shaderCopy(h_.id(), 0, src.id(), 0, bytes)) return;
        glBindBuffer(GL_COPY_READ_BUFFER, src.id());
        glBindBuffer(GL_COPY_WRITE_BUFFER, h_.id());
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, bytes);
    }
    // Copies `bytes` of `src` from byte `srcOffset` to byte `dstOffset` of this buffer, on the GPU.
    void copyRange(const Buffer& src, GLintptr srcOffset, GLintptr dstOffset, GLsizeiptr bytes) const {
        if (bytes <= 0 || detail::shaderCopy(h_.id(), dstOffset, src.id(), srcOffset, bytes)) return;
        glBindBuffer(GL_COPY_READ_BUFFER, src.id());
        glBindBuffer(GL_COPY_WRITE_BUFFER, h_.id());
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, srcOffset, dstOffset, bytes);
    }
    // Becomes the W x H image of 32-bit words in `src` framed by `pad` words
    // of `bits` on every side ((W + 2 pad) x (H + 2 pad) words; storage must
    // be reserved): one shader pass on a hardware GPU, else a driver fill and
    // H row copies.
    void padCopyFrom(const Buffer& src, int W, int H, int pad, GLuint bits) const {
        const GLsizeiptr PW = W + 2 * pad;
        if (detail::shaderPadCopy(h_.id(), src.id(), W, H, pad, bits)) return;
        fill(PW * GLsizeiptr(H + 2 * pad) * 4, bits);
        for (int y = 0; y < H; ++y) copyRange(src, GLintptr(y) * W * 4, (GLintptr(y + pad) * PW + pad) * 4, GLsizeiptr(W) * 4);
    }
    // Reads `bytes` from offset 0 into `out` (waits for the GPU).
    void download(void* out, GLsizeiptr bytes) const {
        glBindBuffer(GL_COPY_READ_BUFFER, h_.id());
        glGetBufferSubData(GL_COPY_READ_BUFFER, 0, bytes, out);
    }

private:
    Handle<detail::BufferDeleter> h_;
    GLsizeiptr size_ = 0;
};

// Makes `tex` a buffer texture over the first `bytes` of `buf` (texelFetch and
// image-buffer access: vectorised on llvmpipe, unlike storage buffers). The
// active unit's buffer-texture binding is left as it was.
inline void attachBufferTexture(const Texture& tex, GLenum format, const Buffer& buf, GLsizeiptr bytes) {
    GLint bound = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_BUFFER, &bound);
    glBindTexture(GL_TEXTURE_BUFFER, tex.id());
    glTexBufferRange(GL_TEXTURE_BUFFER, format, buf.id(), 0, bytes);
    glBindTexture(GL_TEXTURE_BUFFER, GLuint(bound));
}

// Compiles one shader stage; the error carries the driver's log and `name`.
inline Result<Shader> compileShader(GLenum stage, std::string_view source, const std::string& name) {
    Shader s(glCreateShader(stage));
    const GLchar* text = source.data();
    const GLint len = GLint(source.size());
    glShaderSource(s.id(), 1, &text, &len);
    glCompileShader(s.id());
    GLint ok = 0;
    glGetShaderiv(s.id(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint logLen = 0;
        glGetShaderiv(s.id(), GL_INFO_LOG_LENGTH, &logLen);
        std::string log(std::size_t(logLen > 0 ? logLen : 0), '\0');
        if (logLen > 0) glGetShaderInfoLog(s.id(), logLen, nullptr, log.data());
        return makeError(name, "shader compilation failed: " + log);
    }
    return s;
}

// Links the shaders into a program; the error carries the driver's log.
template <class... Shaders>
Result<Program> linkProgram(const std::string& name, const Shaders&... shaders) {
    Program p(glCreateProgram());
    (glAttachShader(p.id(), shaders.id()), ...);
    glLinkProgram(p.id());
    GLint ok = 0;
    glGetProgramiv(p.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint logLen = 0;
        glGetProgramiv(p.id(), GL_INFO_LOG_LENGTH, &logLen);
        std::string log(std::size_t(logLen > 0 ? logLen : 0), '\0');
        if (logLen > 0) glGetProgramInfoLog(p.id(), logLen, nullptr, log.data());
        return makeError(name, "program link failed: " + log);
    }
    return p;
}

// A compute program from one embedded shader source.
inline Result<Program> computeProgram(std::string_view source, const std::string& name) {
    auto cs = compileShader(GL_COMPUTE_SHADER, source, name);
    if (!cs) return cs.error();
    return linkProgram(name, *cs);
}

}  // namespace meniscus::gl
