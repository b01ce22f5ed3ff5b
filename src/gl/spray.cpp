// GL spray drops, docs/pipeline.md#classification,
// docs/pipeline.md#noise-and-foam (the NVIDIA SSFR patent, US 8,947,430, draws
// the particles that left the body of water as spray particles instead of
// surface): the twin of src/cpu/spray.cpp. Each drop is projected with its
// velocity on the host by the CPU's code (shared::sprayDrop of the same
// view-space floats: a few thousand drops, well under a millisecond) and
// uploaded with its rectangle cut into chunks of pixels; on the GPU one
// invocation per chunk adds the drop's fixed-point optical depth where it is in
// front of the fluid and the scene (shaders/spray_splat.comp, atomicAdd: exact
// in any order), so a drop at the camera or a long streak is spread over many
// invocations and no invocation meets llvmpipe's loop cap; then one pass per
// pixel turns the sums into cover and lays the lit drop colour over the image
// in place (shaders/spray_resolve.comp). Formulas: src/shared/spray.h.
#include "gl/spray.h"
#include "gl/gl_backend.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "gl/dispatch.h"
#include "gl/shaders.h"
#include "shared/spray.h"
#include "shared/studio.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kSprayGroup = 64;  // local_size_x of both shaders
// Pixels per work item of spray_splat.comp (most drops are one to a few
// dozen items), and the most items (one round of a kMaxGroups dispatch).
constexpr GLuint kChunkPx = 64;
constexpr std::uint64_t kMaxItems = std::uint64_t(kMaxGroups) * kSprayGroup;
// Pixels per invocation of the resolve (llvmpipe pays a fixed cost per work group).
constexpr GLuint kSprayResolvePerInvocation = 4;

static_assert(sizeof(SprayDrops::Packed) == 48 && offsetof(SprayDrops::Packed, rect) == 32,
              "std430 layout of shared::SprayDrop");

}  // namespace

Result<SprayDrops> SprayDrops::create() {
    SprayDrops s;
    auto splat = loadComputeProgram("spray_splat.comp");
    if (!splat) return splat.error();
    auto resolve = loadComputeProgram("spray_resolve.comp");
    if (!resolve) return resolve.error();
    s.splat_ = std::move(*splat);
    s.resolve_ = std::move(*resolve);
    s.depthTex_ = makeTexture();
    s.sceneTex_ = makeTexture();
    s.sumsTex_ = makeTexture();
    s.colorTex_ = makeTexture();
    s.coverTex_ = makeTexture();
    s.dummy_.reserve(16);
    return s;
}

void SprayDrops::run(const Camera& camera, std::span<const glm::vec3> positionsWorld,
                     std::span<const glm::vec3> velocitiesWorld, float radius, const SprayParams& p,
                     const glm::vec3& lightDirWorld, const GpuImage& depth, const GpuImage* sceneDepth,
                     GpuImage& color, GpuImage& cover, const shared::EnvironmentMap& environment) {
    const int W = camera.width, H = camera.height;
    drawn_ = chunks_ = 0;
    cover.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    const GLuint pixels = GLuint(W) * GLuint(H);
    // No drops on screen, or images of another size (then as the CPU): the
    // cover 0, the colour untouched.
    auto nothing = [&] {
        cover.buffer.fill(cover.bytes(), 0u);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    };
    if (!depth.sized(W, H, 1) || !color.sized(W, H, 4)) return nothing();
    const bool hasScene = sceneDepth && sceneDepth->sized(W, H, 1);

    // The drops on screen: cpu::drawSpray's host code, the same floats in the
    // same order (shared::sprayDropOfWorld).
    const std::size_t n = positionsWorld.size();
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back(), eye = camera.eye;
    const float f = camera.focalPx(), sizeM = p.sizeRadii * radius;
    staging_.clear();
    std::uint64_t totalPixels = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 v = i < velocitiesWorld.size() ? velocitiesWorld[i] : glm::vec3(0.0f);
        shared::SprayDrop s;
        if (!shared::sprayDropOfWorld(positionsWorld[i], v, eye, right, up, back, f, W, H, camera.nearM, sizeM,
                                      p.streakSeconds, p.opacity, s))
            continue;
        if (!(s.rect.x < s.rect.z && s.rect.y < s.rect.w)) continue;
        staging_.push_back({s.a, s.b, s.radiusPx, s.z, s.tau, 0.0f, s.rect});
        totalPixels += std::uint64_t(s.rect.z - s.rect.x) * std::uint64_t(s.rect.w - s.rect.y);
    }
    // The work: each drop's rectangle (row-major) cut into chunks of `chunk`
    // pixels, one per invocation, so every SIMD lane walks about as many
    // pixels as its neighbours whatever the drops' sizes (a long streak or a
    // drop at the camera next to a speck), and none walks more than llvmpipe's
    // 65,535 loop iterations: chunks grow past kChunkPx only to keep the items
    // within one round of the largest dispatch (kMaxItems; a chunk stays under
    // the cap up to 2.7e11 pixels in all).
    const GLuint chunk = GLuint(std::max<std::uint64_t>(kChunkPx, (totalPixels + kMaxItems - 1) / kMaxItems));
    items_.clear();
    for (std::size_t j = 0; j < staging_.size(); ++j) {
        const glm::ivec4 r = staging_[j].rect;
        const GLuint area = GLuint(r.z - r.x) * GLuint(r.w - r.y);
        for (GLuint q = 0; q < area; q += chunk) items_.push_back({GLuint(j), q});
    }
    drawn_ = GLuint(staging_.size());
    chunks_ = GLuint(items_.size());
    if (items_.empty()) return nothing();

    // The sums start at 0 (the driver's fill, a memset on llvmpipe).
    const GLsizeiptr sumBytes = GLsizeiptr(pixels) * 4;
    sums_.reserve(sumBytes);
    sums_.fill(sumBytes, 0u);
    attachBufferTexture(sumsTex_, GL_R32I, sums_, sumBytes);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    // The scatter, one invocation per chunk.
    drops_.upload(staging_.data(), GLsizeiptr(staging_.size() * sizeof(Packed)));
    chunkList_.upload(items_.data(), GLsizeiptr(items_.size() * sizeof(glm::uvec2)));
    attachBufferTexture(depthTex_, GL_R32F, depth.buffer, depth.bytes());
    if (hasScene) attachBufferTexture(sceneTex_, GL_R32F, sceneDepth->buffer, sceneDepth->bytes());
    else attachBufferTexture(sceneTex_, GL_R32F, dummy_, 16);
    glUseProgram(splat_.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, sceneTex_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, drops_.id());
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, sums_.id(), 0, sumBytes);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, chunkList_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, hasScene ? 1 : 0);
    glUniform1ui(2, chunks_);
    glUniform1ui(3, chunk);
    glDispatchCompute(gridGroups(chunks_, kSprayGroup), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);

    // Resolve, per pixel: the cover, and the drops' colour over the image.
    attachBufferTexture(colorTex_, GL_RGBA32F, color.buffer, color.bytes());
    attachBufferTexture(coverTex_, GL_R32F, cover.buffer, cover.bytes());
    glUseProgram(resolve_.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, sumsTex_.id());
    glBindImageTexture(0, colorTex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, coverTex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glUniform1ui(0, pixels);
    glUniform3f(1, p.color.x, p.color.y, p.color.z);
    const glm::vec3 lit = shared::sprayLight(lightDirWorld, back, environment);
    glUniform3f(2, lit.x, lit.y, lit.z);
    glDispatchCompute(gridGroups(pixels, kSprayGroup * kSprayResolvePerInvocation), 1, 1);
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_TEXTURE_FETCH_BARRIER_BIT);
    for (GLenum unit : {GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Drawn over the colour in place: a colour slot that held the cached scene
// no longer does (the next cast redraws it), as the CPU copies its cached
// scene out before painting, never over it.
void runSpray(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.color);
    g.forget(at.spray);
    const FrameSettings& s = g.frame();
    g.pass<SprayDrops>().run(s.camera, s.sprayPositions, s.sprayVelocities, s.radius, s.spray,
                             s.shading.lightDirWorld, g.img(at.depth), &g.img(at.sceneDepth), g.img(at.color),
                             g.img(at.spray), g.frame().environment);
}

}  // namespace

extern const StageDriver kSprayStage = {glPrepare<SprayDrops>, glRun<runSpray>};

}  // namespace meniscus::gl
