// GL surface noise, docs/pipeline.md#noise-and-foam (van der Laan, Green &
// Sainz, US 8,947,430, eqs. 14-17): each particle whose front lies near the
// smoothed surface splats a Gaussian sprite of fractal Perlin noise seeded by
// its id (shaders/noise_splat.comp: the particles that count listed first, then
// one invocation per listed sprite over its rectangle, fixed-point atomicAdd),
// then one pass over the fluid pixels turns the sums into N and bumps the
// normals by its gradient (shaders/noise_resolve.comp). Both follow
// src/cpu/surface_noise.cpp through the shared formulas of
// src/shared/surface_noise.h; the sums are integers, so the image is the
// CPU's bit for bit whatever order the atomics land in. Sprites over 4096
// pixels (near the camera) are spread over many invocations in a further,
// indirect dispatch, as the depth splat does (see noise_splat.comp).
// The velocity whitening map (Cords & Staadt 2008, "Instant Liquids" §4;
// src/cpu/velocity_map.cpp) splats the same sprites with another payload, so
// it runs the same shaders in their whitening mode: two sums per pixel,
// sum(w g whiteness) and sum(w g), and their ratio at the resolve.
#include "gl/surface_noise.h"
#include "gl/gl_backend.h"

#include <algorithm>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kSurfaceNoiseGroup = 64;  // local_size_x of noise_splat.comp
// Work groups per large sprite in noise_splat.comp's pass 2 (as splat.cpp's):
// 4096 invocations, so even a full-screen 4K sprite is ~2,000 pixels (x 7
// loop iterations at 6 octaves) per invocation, below llvmpipe's cap of
// 65,535 loop iterations per invocation.
constexpr GLuint kBigGroups = 64;

}  // namespace

Result<SurfaceNoise> SurfaceNoise::create() {
    SurfaceNoise s;
    auto splat = loadComputeProgram("noise_splat.comp");
    if (!splat) return splat.error();
    auto resolve = loadComputeProgram("noise_resolve.comp");
    if (!resolve) return resolve.error();
    s.splat_ = std::move(*splat);
    s.resolve_ = std::move(*resolve);
    auto segments = FluidSegments::create();
    if (!segments) return segments.error();
    s.segments_ = std::move(*segments);
    s.depthTex_ = makeTexture();
    s.sumsTex_ = makeTexture();
    s.normalsTex_ = makeTexture();
    s.noiseTex_ = makeTexture();
    return s;
}

void SurfaceNoise::scatter(const FrameParams& frame, const Camera& camera, const Buffer& positions, GLuint count,
                           const GpuImage& depth, GLuint planes, const Scatter& sc) {
    const GLuint pixels = GLuint(frame.size.x) * GLuint(frame.size.y);
    attributes_.upload(staging_.data(), GLsizeiptr(staging_.size() * sizeof(glm::vec2)));
    // The sums start at 0 (the driver's fill, a memset on llvmpipe).
    const GLsizeiptr sumBytes = GLsizeiptr(pixels) * GLsizeiptr(planes) * 4;
    sums_.reserve(sumBytes);
    sums_.fill(sumBytes, 0u);
    attachBufferTexture(depthTex_, GL_R32F, depth.buffer, depth.bytes());
    attachBufferTexture(sumsTex_, GL_R32I, sums_, sumBytes);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    if (count == 0) return;

    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
    glUseProgram(splat_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions.id());
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, sums_.id(), 0, sumBytes);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, attributes_.id());
    glUniform1ui(0, count);
    glUniform1f(2, camera.nearM);
    glUniform1f(3, sc.spriteM);
    glUniform1f(4, sc.falloffM);
    if (sc.noise) {
        glUniform1f(5, sc.noise->frequency);
        glUniform1i(6, sc.noise->octaves);
        glUniform1f(7, sc.noise->lacunarity);
        glUniform1f(8, sc.noise->gain);
    }
    glUniform1f(9, sc.sigma);
    glUniform1i(10, sc.whitening ? 1 : 0);
    // Pass 0: the culling, listing the sprites that count, with the indirect
    // dispatches of pass 1 (x = listed / 64, 1, 1) and pass 2 (kBigGroups, listed, 1).
    const GLuint header[8] = {0, 1, 1, 0, kBigGroups, 0, 1, 0};
    lists_.reserve(GLsizeiptr(sizeof header) + 2 * GLsizeiptr(count) * GLsizeiptr(sizeof(GLuint)));
    glBindBuffer(GL_COPY_WRITE_BUFFER, lists_.id());
    glBufferSubData(GL_COPY_WRITE_BUFFER, 0, sizeof header, header);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, lists_.id());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glUniform1i(1, 0);
    glDispatchCompute(gridGroups(count, kSurfaceNoiseGroup), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    // Pass 1: the listed sprites of up to 4096 pixels, one per invocation;
    // pass 2: each listed larger one over kBigGroups work groups.
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, lists_.id());
    glUniform1i(1, 1);
    glDispatchComputeIndirect(0);
    glUniform1i(1, 2);
    glDispatchComputeIndirect(4 * sizeof(GLuint));
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glUseProgram(0);
}

void SurfaceNoise::resolve(GpuImage* normals, GpuImage& out, bool whitening, float jump, float spriteF, float bump) {
    glUseProgram(resolve_.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, sumsTex_.id());
    if (normals) attachBufferTexture(normalsTex_, GL_R32F, normals->buffer, normals->bytes());
    else attachBufferTexture(normalsTex_, GL_R32F, sums_, 4);  // never read nor written
    attachBufferTexture(noiseTex_, GL_R32F, out.buffer, out.bytes());
    glBindImageTexture(0, normalsTex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
    glBindImageTexture(1, noiseTex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glUniform1i(1, normals ? 1 : 0);
    glUniform1f(2, jump);
    glUniform1f(3, spriteF);
    glUniform1f(4, bump);
    glUniform1i(5, whitening ? 1 : 0);
    segments_.bindList(2);
    segments_.dispatch();
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
    glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_TEXTURE_FETCH_BARRIER_BIT);
    for (GLenum unit : {GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glUseProgram(0);
}

void SurfaceNoise::run(const FrameParams& frame, const Camera& camera, const NoiseParams& p, const Buffer& positions,
                       GLuint count, std::span<const float> idz, std::span<const float> amplitude,
                       const GpuImage& depth, GpuImage& normals, GpuImage& noise) {
    const int W = frame.size.x, H = frame.size.y;
    noise.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    // N starts at 0 (a driver fill): the resolve writes only the fluid pixels'.
    noise.buffer.fill(noise.bytes(), 0u);
    if (!depth.sized(W, H, 1)) {  // as the CPU: N = 0, the normals untouched
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    // The CPU's host-side products, the same floats in the same order.
    const float radius = frame.radius;
    Scatter sc;
    sc.spriteM = p.spriteRadii * radius;
    sc.falloffM = p.depthFalloffRadii * radius;
    sc.sigma = p.sigma;
    sc.noise = &p;
    const float jump = defaults::kDepthJumpRadii * radius;
    const float spriteF = p.spriteRadii * radius * camera.focalPx();

    // Per particle (idz, amplitude), with the CPU's defaults.
    staging_.resize(std::max<std::size_t>(count, 1));
    const bool hasAmplitude = amplitude.size() == count;
    for (GLuint i = 0; i < count; ++i)
        staging_[i] = glm::vec2(i < idz.size() ? idz[i] : 0.0f, hasAmplitude ? amplitude[i] : 1.0f);
    segments_.build(depth);  // the 8-pixel row segments with fluid, for the resolve
    scatter(frame, camera, positions, count, depth, 1, sc);

    // Resolve, over the fluid pixels: N, and the normals bumped through
    // noisePerturbedNormal as on the CPU (a zero gradient leaves them as they are).
    resolve(normals.sized(W, H, 3) ? &normals : nullptr, noise, false, jump, spriteF, p.bump);
}

void SurfaceNoise::runWhitening(const FrameParams& frame, const Camera& camera, const WhiteningParams& p,
                                const Buffer& positions, GLuint count, std::span<const float> whiteness,
                                const GpuImage& depth, GpuImage& map) {
    const int W = frame.size.x, H = frame.size.y;
    map.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    map.buffer.fill(map.bytes(), 0u);  // 0 where there is no fluid
    if (!depth.sized(W, H, 1)) {
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    // cpu::splatWhitening's sprites: its own radii and sigma, amplitude 1.
    const float radius = frame.radius;
    Scatter sc;
    sc.whitening = true;
    sc.spriteM = p.spriteRadii * radius;
    sc.falloffM = p.depthFalloffRadii * radius;
    sc.sigma = p.sigma;
    staging_.resize(std::max<std::size_t>(count, 1));
    for (GLuint i = 0; i < count; ++i) staging_[i] = glm::vec2(i < whiteness.size() ? whiteness[i] : 0.0f, 1.0f);
    segments_.build(depth);
    scatter(frame, camera, positions, count, depth, 2, sc);
    resolve(nullptr, map, true, 0.0f, 0.0f, 0.0f);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// The noise N of the particles near the surface, and the normals bumped by its gradient in place.
void runNoise(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.normal);
    g.forget(at.noise);
    const FrameSettings& s = g.frame();
    Splat& particles = g.particles();
    g.pass<SurfaceNoise>().run(g.params(), s.camera, s.noise, particles.particleBuffer(), particles.particleCount(),
                               s.noiseIdz, s.noiseAmplitude, g.img(at.depth), g.img(at.normal), g.img(at.noise));
}

void runWhitening(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.whitening);
    const FrameSettings& s = g.frame();
    Splat& particles = g.particles();
    g.pass<SurfaceNoise>().runWhitening(g.params(), s.camera, s.whitening, particles.particleBuffer(),
                                        particles.particleCount(), s.whiteness, g.img(at.depth),
                                        g.img(at.whitening));
}

}  // namespace

extern const StageDriver kNoiseStage = {glPrepare<SurfaceNoise>, glRun<runNoise>};
extern const StageDriver kWhiteningStage = {glPrepare<SurfaceNoise>, glRun<runWhitening>};

}  // namespace meniscus::gl
