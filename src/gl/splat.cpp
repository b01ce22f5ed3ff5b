// GL depth splat, SPEC §3.3: a compute rasteriser, one invocation per particle
// over its exact projected bounding box with an atomic min on the depth bits
// (shaders/splat_depth.comp). Chosen over point sprites because it needs no
// framebuffer or depth-format round trip, the min is exact on float bits, and
// it runs the CPU reference's arithmetic operation for operation.
#include "gl/splat.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kGroup = 64;          // local_size_x of both shaders
constexpr GLuint kMaxGroups = 65535;   // the minimum GL_MAX_COMPUTE_WORK_GROUP_COUNT; shaders loop past it

// Work groups for `items` with about `perInvocation` items per invocation (the
// shaders loop): llvmpipe pays a fixed cost per work group, so the per-pixel
// passes give each invocation a few pixels.
GLuint groupsFor(GLuint items, GLuint perInvocation = 1) {
    const GLuint perGroup = kGroup * perInvocation;
    return std::clamp<GLuint>((items + perGroup - 1) / perGroup, 1, kMaxGroups);
}
constexpr GLuint kPixelsPerInvocation = 16;

}  // namespace

Result<DepthSplat> DepthSplat::create() {
    DepthSplat s;
    auto splat = loadComputeProgram("splat_depth.comp");
    if (!splat) return splat.error();
    auto resolve = loadComputeProgram("splat_depth_resolve.comp");
    if (!resolve) return resolve.error();
    s.splat_ = std::move(*splat);
    s.resolve_ = std::move(*resolve);
    return s;
}

void DepthSplat::uploadParticles(std::span<const glm::vec3> positionsWorld) {
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "positions are uploaded as packed xyz floats");
    count_ = GLuint(positionsWorld.size());
    // At least one element: binding an empty buffer is an error.
    positions_.reserve(GLsizeiptr(std::max<std::size_t>(1, positionsWorld.size()) * sizeof(glm::vec3)));
    if (!positionsWorld.empty()) positions_.upload(positionsWorld.data(), GLsizeiptr(positionsWorld.size_bytes()));
}

void DepthSplat::run(const Camera& camera, float radius, const Image<float>* sceneDepth) {
    width_ = camera.width;
    height_ = camera.height;
    const GLuint pixels = GLuint(width_) * GLuint(height_);
    depth_.reserve(GLsizeiptr(pixels) * 4);
    const bool hasScene = sceneDepth && sceneDepth->width == width_ && sceneDepth->height == height_;
    if (hasScene) scene_.upload(sceneDepth->pixels.data(), GLsizeiptr(pixels) * 4);
    else scene_.reserve(4);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, depth_.id(), 0, GLsizeiptr(pixels) * 4);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, scene_.id());

    // Clear to the scene depth, or to +inf with the driver's fill (a memset on llvmpipe).
    if (hasScene) {
        glUseProgram(resolve_.id());
        glUniform1ui(0, pixels);
        glUniform1i(1, 1);
        glUniform1i(2, 0);
        glDispatchCompute(groupsFor(pixels, kPixelsPerInvocation), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    } else {
        const GLuint infBits = 0x7f800000u;
        glBindBuffer(GL_COPY_WRITE_BUFFER, depth_.id());
        glClearBufferSubData(GL_COPY_WRITE_BUFFER, GL_R32UI, 0, GLsizeiptr(pixels) * 4, GL_RED_INTEGER, GL_UNSIGNED_INT,
                             &infBits);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }

    // Splat. The view axes and 1/f come from the Camera, rounded as the CPU's.
    if (count_ > 0) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions_.id());
        glUseProgram(splat_.id());
        const float f = camera.focalPx();
        const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back();
        glUniform1ui(0, count_);
        glUniform2i(1, width_, height_);
        glUniform3f(2, camera.eye.x, camera.eye.y, camera.eye.z);
        glUniform3f(3, right.x, right.y, right.z);
        glUniform3f(4, up.x, up.y, up.z);
        glUniform3f(5, back.x, back.y, back.z);
        glUniform1f(6, f);
        glUniform1f(7, 1.0f / f);
        glUniform1f(8, radius);
        glUniform1f(9, std::max(camera.nearM, std::numeric_limits<float>::min()));
        glDispatchCompute(groupsFor(count_), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }

    // Pixels still at the scene depth hold no fluid.
    if (hasScene) {
        glUseProgram(resolve_.id());
        glUniform1i(2, 1);
        glDispatchCompute(groupsFor(pixels, kPixelsPerInvocation), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    } else {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    glUseProgram(0);
}

Image<float> DepthSplat::readDepth() const {
    Image<float> out(width_, height_);
    if (!out.empty()) depth_.download(out.pixels.data(), GLsizeiptr(out.size() * sizeof(float)));
    return out;
}

Result<Image<float>> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                const Image<float>* sceneDepth) {
    auto s = DepthSplat::create();
    if (!s) return s.error();
    s->uploadParticles(positionsWorld);
    s->run(camera, radius, sceneDepth);
    return s->readDepth();
}

}  // namespace meniscus::gl
