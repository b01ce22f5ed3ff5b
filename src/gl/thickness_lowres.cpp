// GL reduced-resolution thickness (docs/pipeline.md#thickness): low-resolution chords
// (shaders/splat.comp with uDiv), the nearest raw depth per block and the
// bilinear upsampling (shaders/thickness_lowres.comp), the blur between them
// (shaders/filter_separable_thickness.comp) -- cpu lowResThickness step by step;
// in two halves for sort-last (the chords' fixed-point sums, then resolved).
#include "gl/thickness_lowres.h"

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kThicknessLowresGroup = 64;          // local_size_x of the shader
constexpr GLuint kThicknessLowresPerInvocation = 16;  // pixels per invocation (the shader loops)

void dispatchPixels(GLuint pixels) { glDispatchCompute(gridGroups(pixels, kThicknessLowresGroup * kThicknessLowresPerInvocation), 1, 1); }
}  // namespace

Result<LowResThickness> LowResThickness::create() {
    LowResThickness t;
    auto p = loadComputeProgram("thickness_lowres.comp");
    if (!p) return p.error();
    t.program_ = std::move(*p);
    return t;
}

void LowResThickness::run(const FrameParams& frame, Splat& splat, SeparableFilters& blur, const GpuImage* sceneDepth,
                          const GpuImage& rawDepth, int divisor, GpuImage& thickness) {
    chords(frame, splat, sceneDepth, divisor, low_);
    resolve(frame, splat, blur, rawDepth, divisor, low_, thickness);
}

void LowResThickness::nearestPerBlock(const FrameParams& frame, int divisor, const GpuImage& full, GpuImage& low) {
    const int W = frame.size.x, H = frame.size.y, d = divisor;
    const int w = (W + d - 1) / d, h = (H + d - 1) / d;
    low.resize(w, h, 1);
    glUseProgram(program_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, d);
    glUniform1i(2, 0);
    full.bind(1);
    low.bind(3);
    dispatchPixels(GLuint(w) * GLuint(h));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glUseProgram(0);
}

void LowResThickness::chords(const FrameParams& frame, Splat& splat, const GpuImage* sceneDepth, int divisor,
                             GpuImage& chords) {
    const int W = frame.size.x, H = frame.size.y;
    // The nearest scene depth per block (once per block here, not per sphere
    // and block in the splat) clips the chords.
    const bool hasScene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    if (hasScene) nearestPerBlock(frame, divisor, *sceneDepth, lowScene_);
    splat.runChordsLowRes(frame, hasScene ? &lowScene_ : nullptr, divisor, chords, /*resolve=*/false);
}

void LowResThickness::resolve(const FrameParams& frame, Splat& splat, SeparableFilters& blur, const GpuImage& rawDepth,
                              int divisor, GpuImage& chords, GpuImage& thickness) {
    const int W = frame.size.x, H = frame.size.y, d = divisor;
    thickness.resize(W, H, 1);
    splat.resolveChords(frame, chords);
    // The nearest raw depth per block projects the blur's sigma.
    nearestPerBlock(frame, d, rawDepth, lowDepth_);
    blur.blurThickness(frame, lowDepth_, chords, frame.right.w / float(d));

    // Upsampling onto the fluid pixels.
    glUseProgram(program_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, d);
    glUniform1i(2, 1);
    chords.bind(1);
    rawDepth.bind(2);
    thickness.bind(3);
    dispatchPixels(GLuint(W) * GLuint(H));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace meniscus::gl
