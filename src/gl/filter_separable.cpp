// GL separable filters (docs/pipeline.md#smoothing) and thickness blur
// (docs/pipeline.md#thickness): Gaussian (van der Laan, Green, Sainz, patent
// "System and method for rendering a particle-based fluid surface"), separable
// bilateral (the thesis, Janisz §4.1.2.1; Pham & van Vliet, ICME 2005) and
// binomial (Cords & Staadt, "Instant Liquids", JGT 2008, §2.2) depth smoothing,
// and the Gaussian thickness blur (thesis §4.1.3), as compute passes
// (shaders/filter_separable*; the depth filters' formulas are
// src/shared/separable_filter.h, the CPU's). Every weight comes from the
// shared::KernelTable the CPU uses, uploaded as is, and the kernel sizes are
// computed here from the frame parameters with the CPU's expressions, so GPU
// and CPU differ only by the rounding of one division.
#include "gl/filter_separable.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "gl/dispatch.h"
#include "gl/shaders.h"
#include "shared/kernel_table.h"  // the weights written once for both backends
#include "shared/thickness.h"

namespace meniscus::gl {

namespace {

constexpr GLuint kGroupX = 64;  // local_size_x of the shaders
constexpr GLuint kRows = 16;    // rows per invocation (kRows in the shaders)
// Between passes: the next pass reads the storage-buffer writes through a buffer texture.
constexpr GLbitfield kPassBarrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT;

void dispatchImage(int w, int h) {
    const GLuint gx = ceilDiv(GLuint(w), kGroupX);
    const GLuint gy = std::min(ceilDiv(GLuint(h), kRows), kMaxGroups);  // shaders loop past it
    glDispatchCompute(gx, gy, 1);
}

// Groups of 4 taps covering -(maxRadius + 1) .. maxRadius + 1: enough for
// every kernel of both the depth filters (m <= maxRadius + 1) and the blur.
int groupsPerRadius(int maxRadius) { return (2 * (maxRadius + 1) + 4) / 4; }

void bindTexBuffer(GLuint unit, const Texture& tex, const Buffer& buf, GLenum format, GLsizeiptr bytes) {
    attachBufferTexture(tex, format, buf, bytes);
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_BUFFER, tex.id());
    glActiveTexture(GL_TEXTURE0);
}


}  // namespace

Result<SeparableFilters> SeparableFilters::create() {
    SeparableFilters f;
    auto plain = loadComputeProgram("filter_separable.comp");
    if (!plain) return plain.error();
    auto bilateral = loadComputeProgram("filter_separable_bilateral.comp");
    if (!bilateral) return bilateral.error();
    auto thickness = loadComputeProgram("filter_separable_thickness.comp");
    if (!thickness) return thickness.error();
    auto segments = FluidSegments::create();
    if (!segments) return segments.error();
    f.segments_ = std::move(*segments);
    f.plain_ = std::move(*plain);
    f.bilateral_ = std::move(*bilateral);
    f.thickness_ = std::move(*thickness);
    f.srcTex_ = makeTexture();
    f.tableTex_ = makeTexture();
    return f;
}

int SeparableFilters::ensureTable(CachedTable& t, TableKind kind, int maxRadius, bool withDiffs) {
    const int groups = groupsPerRadius(maxRadius);
    if (t.kind == kind && t.maxRadius == maxRadius) return groups;
    const shared::KernelTable table = kind == TableKind::Binomial ? shared::KernelTable::binomial(maxRadius)
                                                                  : shared::KernelTable::gaussian(maxRadius);
    // Per radius n the taps in groups of shared::kTapGroup: the depth filters
    // use taps -m .. m (m = n + 1) with the blend row(n) + t diff(n), the
    // thickness blur taps -n .. n of row(n). Texels (4 floats) of one group:
    // row values, then (withDiffs) the differences. Past the radius the CPU
    // rows are zero-padded (padPx covers the round-up).
    const int rows = table.maxRadius() + 1;
    std::vector<float> data;
    data.reserve(std::size_t(rows) * groups * 4 * (withDiffs ? 2 : 1));
    for (int n = 0; n < rows; ++n) {
        const int first = withDiffs ? -(n + 1) : -n;
        for (int j = 0; j < groups; ++j) {
            for (int l = 0; l < 4; ++l) {
                const int k = first + 4 * j + l;
                data.push_back(std::abs(k) <= table.padPx() ? table.row(n)[k] : 0.0f);
            }
            if (withDiffs)
                for (int l = 0; l < 4; ++l) {
                    const int k = first + 4 * j + l;
                    data.push_back(std::abs(k) <= table.padPx() ? table.diff(n)[k] : 0.0f);
                }
        }
    }
    t.buffer.upload(data.data(), GLsizeiptr(data.size() * sizeof(float)));
    t.kind = kind;
    t.maxRadius = maxRadius;
    return groups;
}

std::optional<SeparableKind> separableKind(const FilterParams& filter) {
    if (std::holds_alternative<GaussianParams>(filter)) return SeparableKind::Gaussian;
    if (std::holds_alternative<BilateralParams>(filter)) return SeparableKind::Bilateral;
    if (std::holds_alternative<BinomialParams>(filter)) return SeparableKind::Binomial;
    return std::nullopt;
}

void SeparableFilters::run(const FrameParams& frame, SeparableKind filter, const GpuImage& in, GpuImage& out) {
    const int w = in.width, h = in.height;
    const float radius = frame.radius, focalPx = frame.right.w;
    // Per kind, exactly the CPU's filter{Gaussian,Bilateral,Binomial}: the
    // table, the kernel's world radius and the range weight.
    TableKind kind = TableKind::None;
    float kernelWorldM = 0.0f, rangeSigmaM = 0.0f;
    switch (filter) {  // every kind, no default: a new kind is a compiler warning here
        case SeparableKind::Gaussian:
            kind = TableKind::Gaussian;
            kernelWorldM = 3.0f * frame.gaussianSigmaRadii * radius;
            break;
        case SeparableKind::Bilateral:
            kind = TableKind::Gaussian;
            kernelWorldM = 3.0f * frame.bilateralSigmaRadii * radius;
            rangeSigmaM = frame.bilateralRangeSigmaRadii * radius;
            break;
        case SeparableKind::Binomial:
            kind = TableKind::Binomial;
            kernelWorldM = frame.binomialSizeRadii * radius;
            break;
    }
    if (kind == TableKind::None || frame.filterIterations <= 0 || w <= 0 || h <= 0) {
        out.copyFrom(in);
        glMemoryBarrier(kPassBarrier | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    const int maxRadius = std::max(0, frame.filterMaxKernelPx);  // as KernelTable clamps it
    const int groups = ensureTable(filterTable_, kind, maxRadius, true);
    const float kernelPxDepth = kernelWorldM * focalPx;
    const float jumpM = frame.filterJumpRadii * radius;

    out.resize(w, h, 1);
    scratch_.resize(w, h, 1);
    const bool bilateral = filter == SeparableKind::Bilateral;
    const Program& prog = bilateral ? bilateral_ : plain_;
    glUseProgram(prog.id());
    glUniform2i(0, w, h);
    glUniform1f(2, kernelPxDepth);
    glUniform1f(3, jumpM);
    glUniform1i(4, maxRadius);
    glUniform1i(5, groups);
    if (bilateral) {
        // RangeGaussian's scale: sigma <= 0 (or NaN) keeps only equal depths.
        const double s = double(rangeSigmaM);
        const float scale =
            rangeSigmaM > 0.0f ? float(1.0 / (2.0 * s * s * std::log(2.0))) : std::numeric_limits<float>::max();
        glUniform1f(6, scale);
    }
    bindTexBuffer(1, tableTex_, filterTable_.buffer, GL_RGBA32F, filterTable_.buffer.size());
    // Iteration 0 reads `in`; later ones `out`. x pass -> scratch, y pass -> out.
    for (int it = 0; it < frame.filterIterations; ++it) xyPasses(it == 0 ? in : out, out);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

void SeparableFilters::xyPasses(const GpuImage& src, GpuImage& dst, const FluidSegments* segments) {
    const int w = src.width, h = src.height;
    auto dispatch = [&] {
        if (segments) segments->dispatch();
        else dispatchImage(w, h);
    };
    bindTexBuffer(0, srcTex_, src.buffer, GL_R32F, src.bytes());
    scratch_.bind(1);
    glUniform1i(1, 0);
    dispatch();
    glMemoryBarrier(kPassBarrier);
    bindTexBuffer(0, srcTex_, scratch_.buffer, GL_R32F, scratch_.bytes());
    dst.bind(1);
    glUniform1i(1, 1);
    dispatch();
    glMemoryBarrier(kPassBarrier);
}

void SeparableFilters::blurThickness(const FrameParams& frame, const GpuImage& rawDepth, GpuImage& thickness) {
    blurThickness(frame, rawDepth, thickness, frame.right.w);
}

void SeparableFilters::blurThickness(const FrameParams& frame, const GpuImage& rawDepth, GpuImage& thickness,
                                     float focalPx) {
    const int maxR = shared::thicknessBlurCapPx(frame.thicknessMaxKernelPx);
    if (!(frame.thicknessBlurSigmaRadii > 0.0f) || maxR == 0) return;
    const int w = thickness.width, h = thickness.height;
    if (rawDepth.width != w || rawDepth.height != h || w <= 0 || h <= 0) return;
    const int groups = ensureTable(thicknessTable_, TableKind::Gaussian, maxR, false);
    // cpu thickness.cpp: worldRadiusM = 3 sigma r, kPxDepth = worldRadiusM * f.
    const float worldRadiusM = 3.0f * frame.thicknessBlurSigmaRadii * frame.radius;
    const float kPxDepth = worldRadiusM * focalPx;

    // Only the fluid pixels of the raw depth change; the others are copies,
    // already in place once the scratch image starts as the source.
    segments_.build(rawDepth);
    scratch_.copyFrom(thickness);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(thickness_.id());
    glUniform2i(0, w, h);
    glUniform1f(2, kPxDepth);
    glUniform1i(3, maxR);
    glUniform1i(4, groups);
    bindTexBuffer(1, tableTex_, thicknessTable_.buffer, GL_RGBA32F, thicknessTable_.buffer.size());
    rawDepth.bind(3);
    segments_.bindList(2);
    xyPasses(thickness, thickness, &segments_);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace meniscus::gl
