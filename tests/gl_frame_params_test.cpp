// The shared parameter block (src/shared/frame_params.h): the std140 layout the
// GLSL compiler gives it must be the C++ struct's byte for byte, or every
// shader would read the wrong parameters. A shader copies each field out of the
// uploaded block; the copy must equal packFrameParams' values.
#include <cstring>

#include <gtest/gtest.h>

#include "gl/gpu_image.h"
#include "gl/shaders.h"
#include "gl/uniforms.h"
#include "gl_test_util.h"

namespace gl_frame_params_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {
class GlFrameParams : public GlTest {};
}  // namespace

TEST_F(GlFrameParams, Std140LayoutMatchesCpp) {
    Camera cam;
    cam.eye = {1.0f, 2.0f, 3.0f};
    cam.width = 321;
    cam.height = 123;
    ShadingParams shading;
    ASSERT_TRUE(materialPreset("lava", &shading.material));
    ThicknessParams th;
    th.resolutionDivisor = 2;
    const gl::FrameParams p = gl::packFrameParams(cam, 0.025f, BilateralParams{}, th, shading);

    // Every field, in declaration order, as raw 32-bit words.
    const std::string src = std::string("#version 430 core\n") + std::string(gl::shaderSource("frame_params.h")) + R"(
layout(local_size_x = 1) in;
layout(std430, binding = 1) buffer Out { uint o[]; };
void main() {
    int k = 0;
    for (int c = 0; c < 4; ++c) o[k++] = floatBitsToUint(P.eye[c]);
    for (int c = 0; c < 4; ++c) o[k++] = floatBitsToUint(P.right[c]);
    for (int c = 0; c < 4; ++c) o[k++] = floatBitsToUint(P.up[c]);
    for (int c = 0; c < 4; ++c) o[k++] = floatBitsToUint(P.back[c]);
    for (int c = 0; c < 4; ++c) o[k++] = uint(P.size[c]);
    for (int c = 0; c < 4; ++c) o[k++] = floatBitsToUint(P.fluidColor[c]);
    for (int c = 0; c < 4; ++c) o[k++] = floatBitsToUint(P.absorptionPerM[c]);
    for (int c = 0; c < 4; ++c) o[k++] = floatBitsToUint(P.lightDirWorld[c]);
    o[k++] = floatBitsToUint(P.radius); o[k++] = floatBitsToUint(P.normalsJumpRadii);
    o[k++] = floatBitsToUint(P.specular); o[k++] = floatBitsToUint(P.shininess);
    o[k++] = uint(P.filterKind); o[k++] = uint(P.filterIterations);
    o[k++] = floatBitsToUint(P.filterJumpRadii); o[k++] = uint(P.filterMaxKernelPx);
    o[k++] = floatBitsToUint(P.gaussianSigmaRadii); o[k++] = floatBitsToUint(P.bilateralSigmaRadii);
    o[k++] = floatBitsToUint(P.bilateralRangeSigmaRadii); o[k++] = floatBitsToUint(P.binomialSizeRadii);
    o[k++] = floatBitsToUint(P.cfAlpha); o[k++] = floatBitsToUint(P.nrFilterSizeRadii);
    o[k++] = floatBitsToUint(P.nrLambda); o[k++] = floatBitsToUint(P.nrMu);
    o[k++] = uint(P.nrSeparable); o[k++] = floatBitsToUint(P.thicknessWeight);
    o[k++] = floatBitsToUint(P.thicknessBlurSigmaRadii); o[k++] = uint(P.thicknessMaxKernelPx);
    o[k++] = uint(P.thicknessResolutionDivisor); o[k++] = floatBitsToUint(P.thicknessMinRadii);
    o[k++] = uint(P.pad0); o[k++] = uint(P.pad1);
}
)";
    auto prog = gl::computeProgram(src, "frame_params echo");
    ASSERT_TRUE(prog.ok()) << prog.error().describe();
    gl::FrameParamsBlock block;
    block.upload(p);
    constexpr int kWords = int(sizeof(gl::FrameParams) / 4);
    static_assert(kWords == 56);
    gl::GpuImage out;
    out.resize(kWords, 1, 1);
    out.bind(1);
    glUseProgram(prog->id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const Image<float> got = out.download<float>();
    ASSERT_EQ(got.size(), std::size_t(kWords));
    std::uint32_t want[kWords];
    std::memcpy(want, &p, sizeof p);
    for (int k = 0; k < kWords; ++k) {
        std::uint32_t g;
        std::memcpy(&g, &got.pixels[std::size_t(k)], 4);
        EXPECT_EQ(g, want[k]) << "word " << k;
    }
    EXPECT_EQ(p.size.x, 321);
    EXPECT_EQ(p.filterKind, 2);
    EXPECT_GT(p.bilateralRangeSigmaRadii, 0.0f);
}

TEST_F(GlFrameParams, IncludesResolveAndMissingOnesAreErrors) {
    auto ok = gl::resolveIncludes("splat.comp");
    ASSERT_TRUE(ok.ok()) << ok.error().describe();
    EXPECT_EQ(ok->find("#include"), std::string::npos);
    auto missing = gl::resolveIncludes("no_such_shader.comp");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().describe().find("no_such_shader.comp"), std::string::npos);
}
}  // namespace gl_frame_params_test_local
