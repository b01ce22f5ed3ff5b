// See padded_passes.h.
#include "gl/padded_passes.h"

#include <utility>

namespace meniscus::gl {

PaddedPasses PaddedPasses::create() {
    PaddedPasses p;
    p.texA_ = makeTexture();
    p.texB_ = makeTexture();
    p.outTex_ = makeTexture();
    return p;
}

void PaddedPasses::load(const GpuImage& in, int pad, GLuint frameBits, const GpuImage& out) {
    const int W = in.width, H = in.height, PW = W + 2 * pad;
    const GLsizeiptr paddedBytes = GLsizeiptr(PW) * GLsizeiptr(H + 2 * pad) * 4;
    for (Buffer* buf : {&a_, &b_}) {
        buf->reserve(paddedBytes);
        buf->padCopyFrom(in.buffer, W, H, pad, frameBits);
    }
    attachBufferTexture(texA_, GL_R32F, a_, paddedBytes);
    attachBufferTexture(texB_, GL_R32F, b_, paddedBytes);
    attachBufferTexture(outTex_, GL_R32F, out.buffer, out.bytes());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
}

void PaddedPasses::run(int passes, const FluidSegments& segments,
                       const std::function<void(int, bool)>& beforePass) const {
    glActiveTexture(GL_TEXTURE0);
    const Texture* src = &texA_;
    const Texture* dst = &texB_;
    for (int i = 0; i < passes; ++i) {
        const bool last = i + 1 == passes;
        beforePass(i, last);
        glBindTexture(GL_TEXTURE_BUFFER, src->id());
        glBindImageTexture(0, last ? outTex_.id() : dst->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        segments.dispatch();
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        std::swap(src, dst);
    }
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
}

}  // namespace meniscus::gl
