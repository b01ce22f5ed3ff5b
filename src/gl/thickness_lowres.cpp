// GL reduced-resolution thickness (SPEC §3.4): low-resolution chords
// (shaders/splat.comp with uDiv), the nearest raw depth per block and the
// bilinear upsampling (shaders/thickness_lowres.comp), the blur between them
// (shaders/filter_separable_thickness.comp) -- cpu lowResThickness step by step.
#include "gl/thickness_lowres.h"

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kGroup = 64;          // local_size_x of the shader
constexpr GLuint kPerInvocation = 16;  // pixels per invocation (the shader loops)

void dispatchPixels(GLuint pixels) { glDispatchCompute(gridGroups(pixels, kGroup * kPerInvocation), 1, 1); }
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
    const int W = frame.size.x, H = frame.size.y, d = divisor;
    const int w = (W + d - 1) / d, h = (H + d - 1) / d;
    thickness.resize(W, H, 1);

    glUseProgram(program_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, d);
    glUniform1i(2, 0);
    // The nearest depth per block: of the scene (once per block here, not per
    // sphere and block in the splat) and of the raw fluid depth.
    auto nearestPerBlock = [&](const GpuImage& full, GpuImage& low) {
        low.resize(w, h, 1);
        full.bind(1);
        low.bind(3);
        dispatchPixels(GLuint(w) * GLuint(h));
    };
    const bool hasScene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H;
    if (hasScene) nearestPerBlock(*sceneDepth, lowScene_);
    nearestPerBlock(rawDepth, lowDepth_);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);

    splat.runChordsLowRes(frame, hasScene ? &lowScene_ : nullptr, d, low_);

    blur.blurThickness(frame, lowDepth_, low_, frame.right.w / float(d));

    // Upsampling onto the fluid pixels.
    glUseProgram(program_.id());
    low_.bind(1);
    rawDepth.bind(2);
    thickness.bind(3);
    glUniform1i(2, 1);
    dispatchPixels(GLuint(W) * GLuint(H));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace meniscus::gl
