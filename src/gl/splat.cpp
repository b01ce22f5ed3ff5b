// GL depth splat and thickness chords, docs/pipeline.md#depth-splat,
// docs/pipeline.md#thickness: a compute rasteriser, one invocation per particle
// over its exact projected bounding box, with an atomic min on the depth bits and
// a fixed-point atomic add for the chords (shaders/splat.comp); the CPU
// reference's formulas (src/shared/splat.h, ellipsoid.h, splat_chords.h). Spheres over 4096 pixels (near
// the camera) are listed and spread over many invocations in a second, indirect
// dispatch (see splat.comp).
// Chosen over GL's own rasteriser because it measured faster on Mesa llvmpipe,
// what CI runs. The rasteriser variant (point sprites or quads over the same
// rectangles, the same ray test per fragment, blended into R32F attachments:
// GL_MIN for the depth, GL_FUNC_ADD for the chords, in particle order and so
// bit-identical to the CPU) took, for the bench's depth-splat+thickness line
// (frame 21, 117,649 particles, 1280x720, 2 cores, blur included), a median
// of 144 ms as points and 198 ms as instanced quads against 112 ms here over
// six alternating runs (1.15x and 1.6x in a second, busier session): llvmpipe
// spends ~30 ms on setup and rasterisation of the 117k few-pixel primitives
// before any shading, and runs the vertex stage of an instanced draw once per
// instance.
#include "gl/splat.h"
#include "shared/thickness.h"
#include "gl/thickness_lowres.h"
#include "gl/filter_separable.h"
#include "gl/gl_backend.h"

#include <algorithm>
#include <vector>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kSplatGroup = 64;  // local_size_x of both shaders
constexpr GLuint kPixelsPerInvocation = 16;  // splat_resolve.comp (grid-stride)
// Work groups per large sphere in splat.comp's pass 1: 4096 invocations, so a
// full-screen rectangle even at 4K is a few hundred pixels per invocation,
// far below llvmpipe's cap of 65,535 loop iterations per invocation.
constexpr GLuint kBigGroups = 64;

}  // namespace

Result<Splat> Splat::create() {
    Splat s;
    auto splat = loadComputeProgram("splat.comp");
    if (!splat) return splat.error();
    auto resolve = loadComputeProgram("splat_resolve.comp");
    if (!resolve) return resolve.error();
    s.splat_ = std::move(*splat);
    s.resolve_ = std::move(*resolve);
    s.noScene_.reserve(4);
    s.sceneTex_ = makeTexture();
    s.depthTex_ = makeTexture();
    return s;
}

void Splat::uploadParticles(std::span<const glm::vec3> positionsWorld, std::span<const EllipsoidShape> shapes) {
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "positions are uploaded as packed xyz floats");
    count_ = GLuint(positionsWorld.size());
    // At least one element: binding an empty buffer is an error.
    positions_.reserve(GLsizeiptr(std::max<std::size_t>(1, positionsWorld.size()) * sizeof(glm::vec3)));
    if (!positionsWorld.empty()) positions_.upload(positionsWorld.data(), GLsizeiptr(positionsWorld.size_bytes()));
    ellipsoids_ = !shapes.empty() && shapes.size() == positionsWorld.size();
    if (!ellipsoids_) return;
    // The symmetric m and q packed as splat.comp's Shapes block reads them.
    std::vector<float>& packed = packedShapes_;  // kept across frames: no allocation per frame
    packed.resize(shapes.size() * 12);
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        const glm::mat3 &m = shapes[i].m, &q = shapes[i].q;
        float* o = &packed[12 * i];
        const float v[12] = {m[0][0], m[0][1], m[0][2], m[1][1], m[1][2], m[2][2],
                             q[0][0], q[0][1], q[0][2], q[1][1], q[1][2], q[2][2]};
        std::copy(v, v + 12, o);
    }
    shapes_.reserve(GLsizeiptr(packed.size() * sizeof(float)));
    shapes_.upload(packed.data(), GLsizeiptr(packed.size() * sizeof(float)));
}

void Splat::run(const FrameParams& frame, const GpuImage* sceneDepth, GpuImage& depth, GpuImage* thickness) {
    runAt(frame, sceneDepth, &depth, thickness, 1, true);
}

void Splat::runChordsLowRes(const FrameParams& frame, const GpuImage* sceneDepth, int divisor, GpuImage& thickness,
                            bool resolve) {
    runAt(frame, sceneDepth, nullptr, &thickness, divisor, resolve);
}

void Splat::runPartial(const FrameParams& frame, const GpuImage* sceneDepth, GpuImage& depth, GpuImage& chords) {
    runAt(frame, sceneDepth, &depth, &chords, 1, false);
}

void Splat::resolveChords(const FrameParams& frame, GpuImage& chords) {
    const GLuint pixels = GLuint(chords.width) * GLuint(chords.height);
    chords.bind(3);
    glUseProgram(resolve_.id());
    glUniform1ui(0, pixels);
    glDispatchCompute(gridGroups(pixels, kSplatGroup * kPixelsPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

void Splat::runAt(const FrameParams& frame, const GpuImage* sceneDepth, GpuImage* depth, GpuImage* thickness,
                  int divisor, bool resolve) {
    const int W = frame.size.x, H = frame.size.y, d = divisor;
    const int outW = (W + d - 1) / d, outH = (H + d - 1) / d;
    const GLuint pixels = GLuint(outW) * GLuint(outH);
    if (depth) depth->resize(W, H, 1);
    if (thickness) thickness->resize(outW, outH, 1);
    // The scene depth is on the output grid (see runChordsLowRes).
    const bool hasScene =
        sceneDepth && sceneDepth->width == outW && sceneDepth->height == outH && sceneDepth->channels == 1;
    auto bindOr = [&](const GpuImage* img, GLuint binding) {
        if (img) img->bind(binding);
        else glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, noScene_.id());
    };
    bindOr(depth, 1);
    bindOr(thickness, 3);
    if (hasScene) attachBufferTexture(sceneTex_, GL_R32F, sceneDepth->buffer, sceneDepth->bytes());
    else attachBufferTexture(sceneTex_, GL_R32F, noScene_, 4);
    if (depth) attachBufferTexture(depthTex_, GL_R32F, depth->buffer, depth->bytes());
    else attachBufferTexture(depthTex_, GL_R32F, noScene_, 4);

    // Clear: depth to +inf, chords to 0 (the driver's fills, memsets on
    // llvmpipe); the splat keeps only hits strictly in front of the scene.
    if (depth) depth->buffer.fill(depth->bytes(), 0x7f800000u);
    if (thickness) thickness->buffer.fill(thickness->bytes(), 0u);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    if (count_ > 0) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions_.id());
        glUseProgram(splat_.id());
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_BUFFER, sceneTex_.id());
        glUniform1ui(0, count_);
        glUniform1i(1, hasScene ? 1 : 0);
        glUniform1i(2, thickness ? 1 : 0);
        glUniform1i(4, d);
        glUniform1i(5, ellipsoids_ ? 1 : 0);
        if (ellipsoids_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, shapes_.id());
        else glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, noScene_.id());
        // Pass 0: spheres of up to kMaxPixels pixels, the larger ones listed
        // with pass 1's indirect dispatch (x = kBigGroups, y = listed, z = 1).
        const GLuint header[4] = {kBigGroups, 0, 1, 0};
        big_.reserve(GLsizeiptr(sizeof header) + GLsizeiptr(count_) * GLsizeiptr(sizeof(GLuint)));
        glBindBuffer(GL_COPY_WRITE_BUFFER, big_.id());
        glBufferSubData(GL_COPY_WRITE_BUFFER, 0, sizeof header, header);
        glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, big_.id());
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glUniform1i(3, 0);
        glDispatchCompute(gridGroups(count_, kSplatGroup), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        // Pass 1: each listed rectangle over kBigGroups work groups.
        glUniform1i(3, 1);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, big_.id());
        glDispatchComputeIndirect(0);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
        glActiveTexture(GL_TEXTURE0);
    }

    // Resolve: chord sums to metres.
    if (thickness && resolve) {
        glUseProgram(resolve_.id());
        glUniform1ui(0, pixels);
        glDispatchCompute(gridGroups(pixels, kSplatGroup * kPixelsPerInvocation), 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

Result<Image<float>> splatDepth(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                const Image<float>* sceneDepth, std::span<const EllipsoidShape> shapes) {
    auto s = Splat::create();
    if (!s) return s.error();
    FrameParamsBlock block;
    const FrameParams frame = packFrameParams(camera, radius, NoFilter{}, ThicknessParams{}, ShadingParams{});
    block.upload(frame);
    s->uploadParticles(positionsWorld, shapes);
    GpuImage scene, depth;
    if (sceneDepth) scene.upload(*sceneDepth);
    s->run(frame, sceneDepth ? &scene : nullptr, depth, nullptr);
    return depth.download<float>();
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// The depth splat and the thickness (chords, calibration, blur); the
// thickness grid 1, 2 or 4 pixels per block side.
void runSplat(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.raw);
    g.forget(at.thickness);
    const FrameParams& fp = g.params();
    Splat& splat = g.particles();
    const int d = shared::thicknessDivisor(fp.thicknessResolutionDivisor);
    if (d == 1) {
        splat.run(fp, &g.img(at.sceneDepth), g.img(at.raw), &g.img(at.thickness));
        g.pass<SeparableFilters>().blurThickness(fp, g.img(at.raw), g.img(at.thickness));
    } else {
        splat.run(fp, &g.img(at.sceneDepth), g.img(at.raw), nullptr);
        g.pass<LowResThickness>().run(fp, splat, g.pass<SeparableFilters>(), &g.img(at.sceneDepth), g.img(at.raw), d,
                                      g.img(at.thickness));
    }
}

// Sort-last: the splat's depth and fixed-point sums read back for the compositor.
void runSplatPartial(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    const FrameParams& fp = g.params();
    Splat& splat = g.particles();
    const int d = shared::thicknessDivisor(fp.thicknessResolutionDivisor);
    if (d == 1) {
        splat.runPartial(fp, &g.img(at.sceneDepth), g.partialDepth(), g.partialChords());
    } else {
        splat.run(fp, &g.img(at.sceneDepth), g.partialDepth(), nullptr);
        g.pass<LowResThickness>().chords(fp, splat, &g.img(at.sceneDepth), d, g.partialChords());
    }
    io.partial->depth = g.download<float>(g.partialDepth());
    io.partial->chords = g.download<std::uint32_t>(g.partialChords());
}

// Sort-last: the combination uploaded and resolved as runSplat does.
void runResolveSplat(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.raw);
    g.forget(at.thickness);
    const FrameParams& fp = g.params();
    Splat& splat = g.particles();
    g.img(at.raw).upload(io.partial->depth);
    const int d = shared::thicknessDivisor(fp.thicknessResolutionDivisor);
    if (d == 1) {
        g.img(at.thickness).upload(io.partial->chords);  // resolved in place, as runSplat leaves it
        splat.resolveChords(fp, g.img(at.thickness));
        g.pass<SeparableFilters>().blurThickness(fp, g.img(at.raw), g.img(at.thickness));
    } else {
        g.partialChords().upload(io.partial->chords);
        g.pass<LowResThickness>().resolve(fp, splat, g.pass<SeparableFilters>(), g.img(at.raw), d, g.partialChords(),
                                          g.img(at.thickness));
    }
}

}  // namespace

extern const StageDriver kSplatStage = {glPrepare<SeparableFilters, LowResThickness>, glRun<runSplat>};
extern const StageDriver kSplatPartialStage = {glPrepare<SeparableFilters, LowResThickness>, glRun<runSplatPartial>};
extern const StageDriver kResolveSplatStage = {glPrepare<SeparableFilters, LowResThickness>, glRun<runResolveSplat>};

}  // namespace meniscus::gl
