// GL narrow-range filter, docs/pipeline.md#narrow-range-filter (Truong &
// Yuksel, I3D 2018): the CPU's passes over −inf-padded ping-pong buffers (the
// image copied in row by row), one indirect dispatch per pass over the row
// segments that hold fluid (gl/fluid_segments.h;
// shaders/filter_narrow_range_2d.comp or _1d.comp; the last pass writes the
// output, which starts as a copy of the input). Tap tables, built on the host
// from src/shared/narrow_range.h as the CPU's:
//  - 2-D: ONE list for the largest radius, sorted by (d², dy, dx); since d² is
//    the first key, the list for any radius R is its prefix (the offsets with
//    d² <= R²), so every pixel walks the same list, ring by ring (runs of
//    equal d², which share a weight: one weight fetch per ring);
//  - weights: gaussian(d², R) for d² in [0, R²], per R, shared by 2-D and 1-D
//    (the 1-D tap k has d² = k²).
// llvmpipe notes: SSBO loads/stores run one SIMD lane at a time while texel
// fetches and image stores are vectorised, so the filter reads the depth and
// the tables through buffer textures and writes through an image buffer.
#include "gl/filter_narrow_range.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "gl/shaders.h"
#include "shared/narrow_range.h"

namespace meniscus::gl {

Result<NarrowRange> NarrowRange::create() {
    NarrowRange f;
    auto segments = FluidSegments::create();
    if (!segments) return segments.error();
    f.segments_ = std::move(*segments);
    auto filter2D = loadComputeProgram("filter_narrow_range_2d.comp");
    if (!filter2D) return filter2D.error();
    auto filter1D = loadComputeProgram("filter_narrow_range_1d.comp");
    if (!filter1D) return filter1D.error();
    f.filter2D_ = std::move(*filter2D);
    f.filter1D_ = std::move(*filter1D);
    f.passes_ = PaddedPasses::create();
    for (Texture* t : {&f.tapsTex_, &f.ringsTex_, &f.weightsTex_, &f.metaTex_})
        *t = makeTexture();
    return f;
}

void NarrowRange::buildTables(int cap, int paddedWidth) {
    if (cap == tablesCap_ && paddedWidth == tablesWidth_) return;
    const std::vector<shared::DiscTap> offs = shared::narrowRangeHalfDisc(cap);
    // Taps (linear offsets in the padded buffer) and rings: one per distinct
    // d², (index one past its last tap, d²).
    std::vector<GLint> taps, rings;
    taps.reserve(offs.size() + 1);
    for (std::size_t i = 0; i < offs.size(); ++i) {
        taps.push_back(offs[i].dy * paddedWidth + offs[i].dx);
        if (i + 1 == offs.size() || offs[i + 1].d2 != offs[i].d2) {
            rings.push_back(GLint(i + 1));
            rings.push_back(offs[i].d2);
        }
    }
    // meta[R]: rings of radius R's disc (d² <= R²); meta[cap + 1 + R]: where R's weights start.
    std::vector<GLint> meta(2 * std::size_t(cap + 1), 0);
    std::vector<float> weights;
    for (int R = 1; R <= cap; ++R) {
        GLint n = 0;
        while (2 * std::size_t(n) < rings.size() && rings[2 * std::size_t(n) + 1] <= R * R) ++n;
        meta[R] = n;
        meta[cap + 1 + R] = GLint(weights.size());
        for (int d2 = 0; d2 <= R * R; ++d2) weights.push_back(shared::narrowRangeWeight(d2, R));
    }
    if (taps.empty()) taps.push_back(0);  // buffer textures need storage
    if (rings.empty()) rings.assign(2, 0);
    if (weights.empty()) weights.push_back(0.0f);
    auto upload = [](Buffer& buf, const Texture& tex, GLenum format, const void* data, std::size_t bytes) {
        buf.upload(data, GLsizeiptr(bytes));
        attachBufferTexture(tex, format, buf, GLsizeiptr(bytes));
    };
    upload(taps_, tapsTex_, GL_R32I, taps.data(), taps.size() * sizeof(GLint));
    upload(rings_, ringsTex_, GL_RG32I, rings.data(), rings.size() * sizeof(GLint));
    upload(weights_, weightsTex_, GL_R32F, weights.data(), weights.size() * sizeof(float));
    upload(meta_, metaTex_, GL_R32I, meta.data(), meta.size() * sizeof(GLint));
    tablesCap_ = cap;
    tablesWidth_ = paddedWidth;
    tablesLoops_ = int(offs.size() + rings.size() / 2);
}

void NarrowRange::run(const FrameParams& frame, const GpuImage& in, GpuImage& out) {
    const int W = in.width, H = in.height;
    out.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    // Pixels outside the fluid segments keep their input value.
    out.buffer.copyFrom(in.buffer, in.bytes());
    // The tables' largest radius: the CPU's cap before the nearest-depth bound.
    const int cap = std::max(0, std::min(frame.filterMaxKernelPx, std::max(W, H)));
    if (frame.filterIterations <= 0 || !(frame.radius > 0.0f) || cap == 0) {  // as the CPU: unchanged
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    const int pad = cap, PW = W + 2 * pad;
    buildTables(cap, PW);
    // The fluid segments and the nearest depth (the kernel bound).
    // Segments per invocation: a pixel's loops run at most once per ring and
    // tap of the largest disc (2-D) or per tap (1-D), plus one.
    const int loopsPerPixel = (frame.nrSeparable ? cap : tablesLoops_) + 2;
    segments_.build(in, FluidSegments::kLoopBudget / loopsPerPixel);
    // A −inf frame (taps off the image are "in front") with the image inside.
    passes_.load(in, pad, 0xff800000u, out);

    glUseProgram(frame.nrSeparable ? filter1D_.id() : filter2D_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, pad);
    glUniform1i(2, cap);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, segments_.nearestDepthBits().id());
    const std::pair<GLenum, const Texture*> tables[] = {
        {GL_TEXTURE1, &tapsTex_}, {GL_TEXTURE2, &weightsTex_}, {GL_TEXTURE3, &metaTex_}, {GL_TEXTURE4, &ringsTex_}};
    for (const auto& [unit, tex] : tables) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_BUFFER, tex->id());
    }
    segments_.bindList(5);
    passes_.run(frame.filterIterations * (frame.nrSeparable ? 2 : 1), segments_, [&](int i, bool last) {
        glUniform1i(3, frame.nrSeparable && i % 2 == 1 ? PW : 1);
        glUniform1i(4, last ? 1 : 0);
    });
    for (GLenum unit : {GL_TEXTURE5, GL_TEXTURE4, GL_TEXTURE3, GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glUseProgram(0);
}

}  // namespace meniscus::gl
