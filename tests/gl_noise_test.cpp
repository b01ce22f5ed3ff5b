// The GL twin of the surface noise (src/shared/noise.h, included by the
// shaders): the same values as the C++ build bit for bit, on 64 x 64 points
// of two id slices and their fractal sums.
#include <cstring>

#include <gtest/gtest.h>

#include "gl/gpu_image.h"
#include "gl/shaders.h"
#include "gl_test_util.h"
#include "shared/noise.h"

namespace gl_noise_test_local {

using namespace meniscus;
using namespace meniscus::test;

namespace {
class GlNoise : public GlTest {};

// Sample k of a 64 x 64 x 2 grid (x, y, id), the same float operations on both sides.
glm::vec3 samplePoint(int i, int j, int s) {
    return {float(i) * 0.173f - 3.1f, float(j) * 0.119f + 0.4f, float(1000 + 7 * s)};
}
}  // namespace

TEST_F(GlNoise, SameBitsAsTheCpu) {
    const std::string src = std::string("#version 430 core\n") + std::string(gl::shaderSource("noise.h")) + R"(
layout(local_size_x = 64) in;
layout(std430, binding = 1) buffer Out { float o[]; };
void main() {
    int i = int(gl_GlobalInvocationID.x), j = int(gl_GlobalInvocationID.y), s = int(gl_GlobalInvocationID.z);
    precise float x = float(i) * 0.173 - 3.1;
    precise float y = float(j) * 0.119 + 0.4;
    vec3 p = vec3(x, y, float(1000 + 7 * s));
    int k = ((s * 64 + j) * 64 + i) * 2;
    o[k] = noise3(p);
    o[k + 1] = fractalNoise3(p, 4, 2.0, 0.5);
}
)";
    auto prog = gl::computeProgram(src, "noise probe");
    ASSERT_TRUE(prog.ok()) << prog.error().describe();
    gl::GpuImage out;
    out.resize(64 * 64 * 2 * 2, 1, 1);
    out.bind(1);
    glUseProgram(prog->id());
    glDispatchCompute(1, 64, 2);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const Image<float> got = out.download<float>();
    ASSERT_EQ(got.pixels.size(), std::size_t(64 * 64 * 2 * 2));
    int off = 0, nonZero = 0;
    for (int s = 0; s < 2; ++s)
        for (int j = 0; j < 64; ++j)
            for (int i = 0; i < 64; ++i) {
                const glm::vec3 p = samplePoint(i, j, s);
                const std::size_t k = std::size_t(((s * 64 + j) * 64 + i) * 2);
                const float want[2] = {shared::noise3(p), shared::fractalNoise3(p, 4, 2.0f, 0.5f)};
                for (int c = 0; c < 2; ++c) {
                    off += std::memcmp(&want[c], &got.pixels[k + std::size_t(c)], 4) != 0;
                    nonZero += want[c] != 0.0f;
                }
                if (off == 1 && std::memcmp(&want[0], &got.pixels[k], 4) != 0)
                    ADD_FAILURE() << "first difference at " << i << " " << j << " " << s << ": " << want[0] << " vs "
                                  << got.pixels[k];
            }
    EXPECT_EQ(off, 0) << "of " << 64 * 64 * 2 * 2 << " values differ in some bit";
    EXPECT_GT(nonZero, 64 * 64 * 3);
}
}  // namespace gl_noise_test_local
