// Buffer fills and copies by a compute shader (see buffer_fill.h).
#include "gl/buffer_fill.h"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kBufferFillGroup = 256;           // local_size_x of buffer_fill.comp
constexpr GLuint kMaxGroupsX = 65535u;   // GL's guaranteed work-group count per dimension
// Smaller fills and copies stay with the driver: their cost is the call, not
// the bytes, and a shader pass adds a dispatch and two barriers (the
// narrow-range filter's 4-byte counter resets made it 50% slower on the H200).
constexpr GLsizeiptr kMinShaderBytes = 64 * 1024;
thread_local const BufferFill* tCurrent = nullptr;
}  // namespace

Result<BufferFill> BufferFill::create() {
    BufferFill f;
    auto p = loadComputeProgram("buffer_fill.comp");
    if (!p) return p.error();
    f.program_ = std::move(*p);
    GLint align = 0;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    f.offsetAlignment_ = align > 0 ? GLintptr(align) : 256;
    return f;
}

void BufferFill::fill(GLuint dst, GLintptr dstOffset, GLsizeiptr bytes, GLuint bits) const {
    run(dst, dstOffset, 0, 0, bytes, bits, 0, nullptr);
}

void BufferFill::copy(GLuint dst, GLintptr dstOffset, GLuint src, GLintptr srcOffset, GLsizeiptr bytes) const {
    run(dst, dstOffset, src, srcOffset, bytes, 0u, 1, nullptr);
}

void BufferFill::padCopy(GLuint dst, GLuint src, int W, int H, int pad, GLuint bits) const {
    const int padded[3] = {W, H, pad};
    const GLsizeiptr bytes = GLsizeiptr(W + 2 * pad) * GLsizeiptr(H + 2 * pad) * 4;
    run(dst, 0, src, 0, bytes, bits, 2, padded);
}

void BufferFill::run(GLuint dst, GLintptr dstOffset, GLuint src, GLintptr srcOffset, GLsizeiptr bytes,
                     GLuint bits, int mode, const int* padded) const {
    if (bytes <= 0) return;
    // The callers follow a driver fill with their own barrier; a shader write
    // needs the storage barrier before and after, and the caller's program back.
    // The caller's storage bindings 0 and 1 come back after too.
    GLint previous = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &previous);
    GLint boundId[2];
    GLint64 boundStart[2], boundSize[2];
    for (GLuint b = 0; b < 2; ++b) {
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, b, &boundId[b]);
        glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, b, &boundStart[b]);
        glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, b, &boundSize[b]);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(program_.id());
    const GLuint words = GLuint(bytes / 4);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, dst, dstOffset, bytes);
    if (mode == 2) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, src);  // the whole source image
    else glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, src ? src : dst, src ? srcOffset : dstOffset, bytes);
    glUniform1ui(0, bits);
    glUniform1ui(1, words);
    glUniform1i(2, mode);
    if (padded) glUniform3i(3, padded[0], padded[1], padded[2]);
    const GLuint groups = (words + kBufferFillGroup - 1) / kBufferFillGroup;
    const GLuint gx = std::min(groups, kMaxGroupsX);
    glDispatchCompute(gx, (groups + gx - 1) / gx, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(GLuint(previous));
    for (GLuint b = 0; b < 2; ++b) {
        if (boundId[b] != 0 && boundSize[b] > 0)
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER, b, GLuint(boundId[b]), GLintptr(boundStart[b]),
                              GLsizeiptr(boundSize[b]));
        else
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, GLuint(boundId[b]));
    }
}

bool BufferFill::takes(GLintptr dstOffset, GLintptr srcOffset, GLsizeiptr bytes) const {
    return bytes >= kMinShaderBytes && bytes % 4 == 0 && dstOffset % offsetAlignment_ == 0 &&
           srcOffset % offsetAlignment_ == 0;
}

bool isSoftwareRenderer(std::string_view renderer) {
    for (std::string_view soft : {"llvmpipe", "softpipe", "swrast"})
        if (renderer.find(soft) != std::string_view::npos) return true;
    return false;
}

bool useShaderFills(std::string_view renderer) {
    if (const char* v = std::getenv("MENISCUS_GL_FILL")) {
        if (std::string_view(v) == "shader") return true;
        if (std::string_view(v) == "driver") return false;
    }
    return !isSoftwareRenderer(renderer);
}

ScopedBufferFill::ScopedBufferFill(const BufferFill* fill) : previous_(tCurrent) { tCurrent = fill; }
ScopedBufferFill::~ScopedBufferFill() { tCurrent = previous_; }

namespace detail {
bool shaderFill(GLuint dst, GLintptr dstOffset, GLsizeiptr bytes, GLuint bits) {
    if (!tCurrent || !tCurrent->takes(dstOffset, 0, bytes)) return false;
    tCurrent->fill(dst, dstOffset, bytes, bits);
    return true;
}
bool shaderPadCopy(GLuint dst, GLuint src, int W, int H, int pad, GLuint bits) {
    if (!tCurrent) return false;
    tCurrent->padCopy(dst, src, W, H, pad, bits);
    return true;
}
bool shaderCopy(GLuint dst, GLintptr dstOffset, GLuint src, GLintptr srcOffset, GLsizeiptr bytes) {
    if (!tCurrent || src == dst || !tCurrent->takes(dstOffset, srcOffset, bytes)) return false;
    tCurrent->copy(dst, dstOffset, src, srcOffset, bytes);
    return true;
}
}  // namespace detail

}  // namespace meniscus::gl
