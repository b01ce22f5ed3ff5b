// GL narrow-range filter, SPEC §3.5 (Truong & Yuksel, I3D 2018): the CPU's
// passes over −inf-padded ping-pong buffers, one dispatch per pass
// (shaders/filter_narrow_range.comp), after a pad pass that also finds the
// nearest depth on the GPU and before an unpad pass
// (shaders/filter_narrow_range_pad.comp).
// Tap tables, built on the host exactly as the CPU's (weights in double):
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
#include <cmath>
#include <utility>
#include <vector>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kGroup = 64;             // local_size_x of both shaders
constexpr GLuint kCopyPerInvocation = 16; // filter_narrow_range_pad.comp's kPerInvocation
constexpr GLuint kRows = 4;               // filter_narrow_range.comp's kRows

// The CPU's gaussian(d2, R): sigma = R/3, evaluated in double.
float gaussian(int d2, int R) {
    const double sigma = double(R) / 3.0;
    return float(std::exp(-double(d2) / (2.0 * sigma * sigma)));
}

void attach(const Texture& tex, GLenum format, const Buffer& buf, GLsizeiptr bytes) {
    glBindTexture(GL_TEXTURE_BUFFER, tex.id());
    glTexBufferRange(GL_TEXTURE_BUFFER, format, buf.id(), 0, bytes);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
}
}  // namespace

Result<NarrowRange> NarrowRange::create() {
    NarrowRange f;
    auto pad = loadComputeProgram("filter_narrow_range_pad.comp");
    if (!pad) return pad.error();
    auto filter = loadComputeProgram("filter_narrow_range.comp");
    if (!filter) return filter.error();
    f.pad_ = std::move(*pad);
    f.filter_ = std::move(*filter);
    for (Texture* t : {&f.texA_, &f.texB_, &f.tapsTex_, &f.ringsTex_, &f.weightsTex_, &f.metaTex_}) *t = makeTexture();
    return f;
}

void NarrowRange::buildTables(int cap, int paddedWidth) {
    if (cap == tablesCap_ && paddedWidth == tablesWidth_) return;
    struct Off {
        int dx, dy, d2;
    };
    std::vector<Off> offs;
    // Half plane: dy > 0, or dy == 0 and dx > 0; the mirror covers the rest.
    for (int dy = 0; dy <= cap; ++dy)
        for (int dx = -cap; dx <= cap; ++dx) {
            if (dy == 0 && dx <= 0) continue;
            const int d2 = dx * dx + dy * dy;
            if (d2 <= cap * cap) offs.push_back({dx, dy, d2});
        }
    std::sort(offs.begin(), offs.end(), [](const Off& a, const Off& b) {
        if (a.d2 != b.d2) return a.d2 < b.d2;
        if (a.dy != b.dy) return a.dy < b.dy;
        return a.dx < b.dx;
    });
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
        for (int d2 = 0; d2 <= R * R; ++d2) weights.push_back(gaussian(d2, R));
    }
    if (taps.empty()) taps.push_back(0);  // buffer textures need storage
    if (rings.empty()) rings.assign(2, 0);
    if (weights.empty()) weights.push_back(0.0f);
    auto upload = [](Buffer& buf, const Texture& tex, GLenum format, const void* data, std::size_t bytes) {
        buf.upload(data, GLsizeiptr(bytes));
        attach(tex, format, buf, GLsizeiptr(bytes));
    };
    upload(taps_, tapsTex_, GL_R32I, taps.data(), taps.size() * sizeof(GLint));
    upload(rings_, ringsTex_, GL_RG32I, rings.data(), rings.size() * sizeof(GLint));
    upload(weights_, weightsTex_, GL_R32F, weights.data(), weights.size() * sizeof(float));
    upload(meta_, metaTex_, GL_R32I, meta.data(), meta.size() * sizeof(GLint));
    tablesCap_ = cap;
    tablesWidth_ = paddedWidth;
}

void NarrowRange::run(const FrameParams& frame, const GpuImage& in, GpuImage& out) {
    const int W = in.width, H = in.height;
    out.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    // The tables' largest radius: the CPU's cap before the nearest-depth bound.
    const int cap = std::max(0, std::min(frame.filterMaxKernelPx, std::max(W, H)));
    if (frame.filterIterations <= 0 || !(frame.radius > 0.0f) || cap == 0) {  // as the CPU: unchanged
        out.buffer.copyFrom(in.buffer, in.bytes());
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    const int pad = cap, PW = W + 2 * pad;
    const GLsizeiptr paddedBytes = GLsizeiptr(PW) * GLsizeiptr(H + 2 * pad) * 4;
    buildTables(cap, PW);
    a_.reserve(paddedBytes);
    b_.reserve(paddedBytes);
    zMin_.reserve(4);
    // −inf frames (the interiors are overwritten), zMin = +inf: driver fills.
    a_.fill(paddedBytes, 0xff800000u);
    b_.fill(paddedBytes, 0xff800000u);
    zMin_.fill(4, 0x7f800000u);
    attach(texA_, GL_R32F, a_, paddedBytes);
    attach(texB_, GL_R32F, b_, paddedBytes);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    const GLuint pixels = GLuint(W) * GLuint(H);
    glUseProgram(pad_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, 0);
    glUniform1i(2, pad);
    in.bind(1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, a_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, zMin_.id());
    glDispatchCompute(ceilDiv(pixels, kGroup * kCopyPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);

    glUseProgram(filter_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, pad);
    glUniform1i(2, cap);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, tapsTex_.id());
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_BUFFER, weightsTex_.id());
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_BUFFER, metaTex_.id());
    glActiveTexture(GL_TEXTURE4);
    glBindTexture(GL_TEXTURE_BUFFER, ringsTex_.id());
    glActiveTexture(GL_TEXTURE0);
    const Texture* src = &texA_;
    const Texture* dst = &texB_;
    auto pass = [&](int step) {
        glUniform1i(3, step);
        glBindTexture(GL_TEXTURE_BUFFER, src->id());
        glBindImageTexture(0, dst->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glDispatchCompute(ceilDiv(GLuint(W), kGroup), ceilDiv(GLuint(H), kRows), 1);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_SHADER_STORAGE_BARRIER_BIT);
        std::swap(src, dst);
    };
    for (int it = 0; it < frame.filterIterations; ++it) {
        if (frame.nrSeparable) {
            pass(1);
            pass(PW);
        } else {
            pass(0);
        }
    }
    for (GLenum unit : {GL_TEXTURE4, GL_TEXTURE3, GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }

    glUseProgram(pad_.id());
    glUniform1i(1, 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, src == &texA_ ? a_.id() : b_.id());
    out.bind(4);
    glDispatchCompute(ceilDiv(pixels, kGroup * kCopyPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace meniscus::gl
