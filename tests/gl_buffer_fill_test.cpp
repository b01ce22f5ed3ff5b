// Shader fills and copies (src/gl/buffer_fill.h), the path a hardware GPU's
// backend takes instead of the driver's glClearBufferSubData /
// glCopyBufferSubData (slow on NVIDIA, a copy engine), with the rest of a
// hardware GPU's settings (one row segment per invocation, staged read-back).
// CI has only llvmpipe, whose backend keeps its own, so here both are forced
// and must give the same bits: buffer by buffer (offsets, sizes that are not a whole
// work group, the caller's bindings and program kept) and for whole frames
// with every stage that fills or copies (splat, normals, shading, noise,
// whitening, silhouette, spray).
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gl/buffer_fill.h"
#include "gl/objects.h"
#include "gl_test_util.h"

namespace gl_buffer_fill_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {

class GlBufferFill : public GlTest {};

std::vector<std::uint32_t> download(const gl::Buffer& b, std::size_t words) {
    std::vector<std::uint32_t> out(words);
    b.download(out.data(), GLsizeiptr(words * 4));
    return out;
}

TEST_F(GlBufferFill, FillsAndCopiesLikeTheDriver) {
    std::string why;
    ASSERT_TRUE(sharedGlContext(&why)->makeCurrent().ok());
    auto fill = gl::BufferFill::create();
    ASSERT_TRUE(fill.ok()) << fill.error().describe();
    const std::size_t words = 70001;  // not a multiple of the 256-wide work group
    std::vector<std::uint32_t> ramp(words);
    std::iota(ramp.begin(), ramp.end(), 1u);
    gl::Buffer viaShader, viaDriver, source;
    for (gl::Buffer* b : {&viaShader, &viaDriver}) b->upload(ramp.data(), GLsizeiptr(words * 4));
    std::vector<std::uint32_t> other(words, 0xdeadbeefu);
    source.upload(other.data(), GLsizeiptr(words * 4));

    // A caller's program and storage binding 1 survive the shader path.
    gl::Buffer bound;
    bound.reserve(64);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, bound.id(), 0, 64);
    {
        const gl::ScopedBufferFill use(&*fill);
        viaShader.fill(GLsizeiptr(40000 * 4), 0x7f800000u);             // the first 40,000 words: +inf
        viaShader.copyRange(source, 0, GLsizeiptr(50000 * 4), 4 * 17001);  // 17,001 words to word 50,000
        viaShader.copyRange(source, 8, 4, 4 * 20000);  // unaligned offsets: the driver's call
    }
    viaDriver.fill(GLsizeiptr(40000 * 4), 0x7f800000u);
    viaDriver.copyRange(source, 0, GLsizeiptr(50000 * 4), 4 * 17001);
    viaDriver.copyRange(source, 8, 4, 4 * 20000);
    GLint id = 0;
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, 1, &id);
    EXPECT_EQ(GLuint(id), bound.id());
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));

    const auto a = download(viaShader, words), b = download(viaDriver, words);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a[0], 0x7f800000u);
    EXPECT_EQ(a[1], 0xdeadbeefu);
    EXPECT_EQ(a[39999], 0x7f800000u);
    EXPECT_EQ(a[40000], 40001u);  // untouched
    EXPECT_EQ(a[50000], 0xdeadbeefu);
    EXPECT_EQ(a[67000], 0xdeadbeefu);
    EXPECT_EQ(a[67001], 67002u);  // past the copied range

    // Whole-buffer copy.
    gl::Buffer copied;
    copied.reserve(GLsizeiptr(words * 4));
    {
        const gl::ScopedBufferFill use(&*fill);
        copied.copyFrom(viaShader, GLsizeiptr(words * 4));
    }
    EXPECT_EQ(download(copied, words), a);
}

// The filters' padded copy (gl/padded_passes.cpp): an odd-sized image framed
// by 13 words of -inf, as one shader pass and as the driver's fill + row copies.
TEST_F(GlBufferFill, PaddedCopiesLikeTheDriver) {
    std::string why;
    ASSERT_TRUE(sharedGlContext(&why)->makeCurrent().ok());
    auto fill = gl::BufferFill::create();
    ASSERT_TRUE(fill.ok()) << fill.error().describe();
    const int W = 301, H = 77, pad = 13, PW = W + 2 * pad, PH = H + 2 * pad;
    std::vector<std::uint32_t> image(std::size_t(W) * H);
    std::iota(image.begin(), image.end(), 7u);
    gl::Buffer source, viaShader, viaDriver;
    source.upload(image.data(), GLsizeiptr(image.size() * 4));
    for (gl::Buffer* b : {&viaShader, &viaDriver}) b->reserve(GLsizeiptr(PW) * PH * 4);
    {
        const gl::ScopedBufferFill use(&*fill);
        viaShader.padCopyFrom(source, W, H, pad, 0xff800000u);
    }
    viaDriver.padCopyFrom(source, W, H, pad, 0xff800000u);
    const auto a = download(viaShader, std::size_t(PW) * PH), b = download(viaDriver, std::size_t(PW) * PH);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a[0], 0xff800000u);
    EXPECT_EQ(a[std::size_t(pad) * PW + pad], 7u);                                // the image's first pixel
    EXPECT_EQ(a[std::size_t(pad + H - 1) * PW + pad + W - 1], 7u + W * H - 1u);  // and its last
    EXPECT_EQ(a[std::size_t(pad + H - 1) * PW + pad + W], 0xff800000u);          // the frame right of it
}

TEST_F(GlBufferFill, RenderersAreChosenByName) {
    if (std::getenv("MENISCUS_GL_FILL")) GTEST_SKIP() << "MENISCUS_GL_FILL is set";
    EXPECT_FALSE(gl::useShaderFills("llvmpipe (LLVM 15.0.6, 256 bits)"));
    EXPECT_FALSE(gl::useShaderFills("softpipe"));
    EXPECT_TRUE(gl::isSoftwareRenderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
    EXPECT_FALSE(gl::isSoftwareRenderer("NVIDIA H200/PCIe/SSE2"));
    EXPECT_TRUE(gl::useShaderFills("NVIDIA H200/PCIe/SSE2"));
    EXPECT_TRUE(gl::useShaderFills("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.54)"));
}

// Whole frames with a hardware GPU's settings forced on llvmpipe (shader
// fills and copies, one row segment per invocation, read-back through the
// staging buffer) against llvmpipe's own: the same bits in every AOV, with
// every optional stage on.
TEST_F(GlBufferFill, WholeFramesMatchWithAHardwareGpusSettings) {
    RenderSettings s = realFrameSettings(256, 144);
    s.noise.enabled = true;
    s.whitening.enabled = true;
    s.spray.enabled = true;
    s.silhouette.enabled = true;
    const ParticleView view = ParticleView::of(realSet());
    Aovs frames[2];
    for (int k = 0; k < 2; ++k) {
        ::setenv("MENISCUS_GL_FILL", k == 0 ? "driver" : "shader", 1);
        ::setenv("MENISCUS_GL_SEGMENT_ROUNDS", k == 0 ? "16" : "1", 1);
        auto r = Renderer::create(BackendChoice::Gl);
        ::unsetenv("MENISCUS_GL_FILL");
        ::unsetenv("MENISCUS_GL_SEGMENT_ROUNDS");
        ASSERT_TRUE(r.ok()) << r.error().describe();
        auto a = r->render(view, s);
        ASSERT_TRUE(a.ok()) << a.error().describe();
        frames[k] = std::move(*a);
    }
    EXPECT_EQ(differingBits(frames[0].color, frames[1].color), 0);
    EXPECT_EQ(differingBits(frames[0].depth, frames[1].depth), 0);
    EXPECT_EQ(differingBits(frames[0].rawDepth, frames[1].rawDepth), 0);
    EXPECT_EQ(differingBits(frames[0].thickness, frames[1].thickness), 0);
    EXPECT_EQ(differingBits(frames[0].normal, frames[1].normal), 0);
    EXPECT_EQ(differingBits(frames[0].noise, frames[1].noise), 0);
    EXPECT_EQ(differingBits(frames[0].whitening, frames[1].whitening), 0);
    EXPECT_EQ(differingBits(frames[0].spray, frames[1].spray), 0);
    EXPECT_EQ(differingBits(frames[0].silhouette, frames[1].silhouette), 0);
    EXPECT_GT(frames[0].color.size(), 0u);
}

}  // namespace
}  // namespace gl_buffer_fill_test_local
