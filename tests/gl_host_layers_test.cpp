// Embedding (Renderer::drawIntoHost, docs/compositing.md): the liquid drawn
// into a host application's frame, its colour and depth textures and camera
// matrices, on the GL context the host renders with, checked against the CPU
// reference compositing the same layers as a backdrop (kind window:NEAR,FAR),
// within the whole pipeline's colour tolerance (gl_test_util.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "gl_test_util.h"
#include "meniscus/backdrop.h"
#include "shared/srgb.h"

namespace meniscus::gl_host_layers_test_local {
namespace {

using test::GlTest;

class GlHostLayers : public GlTest {};

// A host's frame made as an application makes it: an 8-bit colour texture
// (sRGB codes), a 32-bit float depth texture of window depth, and the
// framebuffer the application draws into (an 8-bit colour attachment).
struct HostFrameGl {
    GLuint color = 0, depth = 0, target = 0, framebuffer = 0;
    int width = 0, height = 0;
    HostFrameGl(int w, int h, const std::vector<std::uint8_t>& rgba, const std::vector<float>& windowDepth)
        : width(w), height(h) {
        glGenTextures(1, &color);
        glBindTexture(GL_TEXTURE_2D, color);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        glGenTextures(1, &depth);
        glBindTexture(GL_TEXTURE_2D, depth);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, w, h, 0, GL_DEPTH_COMPONENT, GL_FLOAT, windowDepth.data());
        glGenTextures(1, &target);
        glBindTexture(GL_TEXTURE_2D, target);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glBindTexture(GL_TEXTURE_2D, 0);
        glGenFramebuffers(1, &framebuffer);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    }
    ~HostFrameGl() {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &framebuffer);
        const GLuint textures[3] = {color, depth, target};
        glDeleteTextures(3, textures);
    }
    std::vector<std::uint8_t> readTarget() const {
        std::vector<std::uint8_t> out(std::size_t(width) * std::size_t(height) * 4);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, out.data());
        return out;
    }
};

// Every 8-bit code decodes (shared::srgbDecodeTable) to a value that the
// present pass and the PNG writer encode back to the same code: the host's
// picture goes through the pipeline unchanged where no liquid covers it.
TEST(HostLayersDecoding, EveryCodeComesBackAsItWent) {
    const auto& table = shared::srgbDecodeTable();
    for (int k = 0; k < 256; ++k) EXPECT_EQ(test::srgb8(table[std::size_t(k)]), k) << k;
    EXPECT_EQ(table[0], 0.0f);
    EXPECT_EQ(table[255], 1.0f);
}

// The host's camera on the real frame, as an application holds it.
HostLayers hostCamera(int W, int H) {
    const Camera framed = test::realFrameCamera(W, H);
    HostLayers host;
    host.width = W;
    host.height = H;
    host.view = glm::lookAt(framed.eye, framed.target, framed.up);
    host.projection = glm::perspective(glm::radians(framed.fovYDegrees), float(W) / float(H), framed.nearM, framed.farM);
    return host;
}

TEST_F(GlHostLayers, TheLiquidInTheHostsFrameIsTheCpusCompositeOfItsLayers) {
    const int W = 320, H = 180;
    const std::vector<glm::vec3>& positions = test::realFrame().positions;
    ASSERT_FALSE(positions.empty());
    RenderSettings settings;
    settings.radiusM = test::realFrame().radius;
    HostLayers host = hostCamera(W, H);
    auto camera = cameraFromGlMatrices(host.view, host.projection, W, H);
    ASSERT_TRUE(camera.ok()) << camera.error().describe();
    settings.camera = *camera;

    // The liquid's depth range, to put the host's surfaces in front of it,
    // among it and behind it.
    Renderer cpu;
    auto plain = cpu.render(positions, settings);
    ASSERT_TRUE(plain.ok()) << plain.error().describe();
    float nearest = INFINITY, farthest = 0.0f;
    for (float z : plain->rawDepth.pixels)
        if (std::isfinite(z)) nearest = std::min(nearest, z), farthest = std::max(farthest, z);
    ASSERT_LT(nearest, farthest);
    // Vertical stripes of the host's picture (GL rows: row 0 at the bottom):
    // a wall in front of the liquid, one among it, one behind it, and the
    // host's sky (window depth 1: nothing).
    const float n = camera->nearM, f = camera->farM;
    auto window = [&](float z) { return (f / (f - n)) * (1.0f - n / z); };
    std::vector<std::uint8_t> rgba;
    std::vector<float> windowDepth;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int stripe = (x / 20) % 4;
            rgba.insert(rgba.end(), {std::uint8_t(40 + 50 * stripe), std::uint8_t(x * 255 / W),
                                     std::uint8_t(y * 255 / H), 255});
            // (the wall in front lies beyond the near plane: a depth texture
            // holds 0 .. 1 only)
            const float z = stripe == 0 ? 0.5f * (n + nearest) : stripe == 1 ? 0.5f * (nearest + farthest)
                            : stripe == 2 ? 2.0f * farthest : 0.0f;
            windowDepth.push_back(stripe == 3 ? 1.0f : window(z));
        }

    // The CPU reference: the same layers as a backdrop (rows top first).
    BackdropImage backdrop;
    backdrop.width = W;
    backdrop.height = H;
    backdrop.convention.kind = BackdropDepthKind::Window;
    backdrop.convention.nearM = n;
    backdrop.convention.farM = f;
    backdrop.name = "the host's layers";
    const auto& decode = shared::srgbDecodeTable();
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = (std::size_t(H - 1 - y) * std::size_t(W) + std::size_t(x));
            backdrop.color.emplace_back(decode[rgba[4 * i]], decode[rgba[4 * i + 1]], decode[rgba[4 * i + 2]], 1.0f);
            backdrop.depth.push_back(windowDepth[i]);
        }
    RenderSettings withBackdrop = settings;
    withBackdrop.scene.backdrop = std::make_shared<const BackdropImage>(std::move(backdrop));
    auto want = cpu.render(positions, withBackdrop);
    ASSERT_TRUE(want.ok()) << want.error().describe();

    // GL: the host's frame, drawn into by a renderer on the host's context.
    auto gl = Renderer::createOnCurrentGlContext();
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    {
        HostFrameGl frame(W, H, rgba, windowDepth);
        host.colorTexture = frame.color;
        host.depthTexture = frame.depth;
        glBindFramebuffer(GL_FRAMEBUFFER, frame.framebuffer);
        glViewport(3, 4, 50, 60);  // the host's own, given back
        auto st = gl->drawIntoHost(positions, settings, host);
        ASSERT_TRUE(st.ok()) << st.error().describe();
        GLint viewport[4], bound = 0;
        glGetIntegerv(GL_VIEWPORT, viewport);
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
        EXPECT_EQ(viewport[0], 3);
        EXPECT_EQ(viewport[3], 60);
        EXPECT_EQ(GLuint(bound), frame.framebuffer);
        const std::vector<std::uint8_t> got = frame.readTarget();

        // Compared in 8-bit sRGB steps, the GL frame's rows flipped.
        Image<glm::vec4> drawn(W, H);
        int untouched = 0, liquidInFront = 0, hidden = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(H - 1 - y) * std::size_t(W) + std::size_t(x);
                drawn.at(x, y) = glm::vec4(decode[got[4 * i]], decode[got[4 * i + 1]], decode[got[4 * i + 2]], 1.0f);
                const bool liquid = std::isfinite(plain->rawDepth.at(x, y));
                const bool same = got[4 * i] == rgba[4 * i] && got[4 * i + 1] == rgba[4 * i + 1] &&
                                  got[4 * i + 2] == rgba[4 * i + 2];
                if (!liquid) untouched += same;
                // The wall in front of the liquid hides it: the host's own codes.
                if (liquid && (x / 20) % 4 == 0) hidden += same;
                if (liquid && (x / 20) % 4 == 3) liquidInFront += !same;
            }
        Image<glm::vec4> reference = want->color;
        for (glm::vec4& c : reference.pixels) c.a = 1.0f;  // a framebuffer's alpha is not compared
        const test::ColorDiff d = test::expectPipelineColor(reference, drawn, "embedded frame");
        std::printf("embedded vs CPU backdrop: max %d steps, %.4f%% over 1\n", d.maxSteps, 100.0 * d.fractionOver1);
        EXPECT_GT(untouched, W * H / 4);  // the host's picture around the liquid is kept
        EXPECT_GT(hidden, 100);
        EXPECT_GT(liquidInFront, 100);  // and the liquid is in it
    }
    // A CPU renderer cannot, and says so.
    auto refused = cpu.drawIntoHost(positions, settings, host);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().describe().find("GL renderer"), std::string::npos) << refused.error().describe();
}

// A host's frame of one colour with nothing in its depth (window depth 1),
// its textures and the real frame's camera in `host`.
struct PlainHost {
    std::vector<std::uint8_t> rgba;
    HostFrameGl frame;
    HostLayers host;
    static std::vector<std::uint8_t> colour(int W, int H) {
        std::vector<std::uint8_t> out;
        for (int i = 0; i < W * H; ++i) out.insert(out.end(), {90, 120, 150, 255});
        return out;
    }
    PlainHost(int W, int H)
        : rgba(colour(W, H)), frame(W, H, rgba, std::vector<float>(std::size_t(W) * std::size_t(H), 1.0f)),
          host(hostCamera(W, H)) {
        host.colorTexture = frame.color;
        host.depthTexture = frame.depth;
    }
};

// A host's particles in its own GL buffer, laid out as an application's
// vertex buffer may be: a header of `offset` bytes, then per particle
// x, y, z and a fourth float it uses for itself (NaN here: never read).
struct HostParticlesGl {
    GLuint buffer = 0;
    HostParticleBuffer view;
    HostParticlesGl(const std::vector<glm::vec3>& positions, std::size_t offset) {
        std::vector<float> words(offset / 4, -7.0f);
        for (const glm::vec3& p : positions) words.insert(words.end(), {p.x, p.y, p.z, NAN});
        glGenBuffers(1, &buffer);
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(words.size() * sizeof(float)), words.data(), GL_STATIC_DRAW);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        view.buffer = buffer;
        view.count = positions.size();
        view.offsetBytes = offset;
        view.strideBytes = 16;
        for (const glm::vec3& p : positions) view.bounds.extend(p);
    }
    ~HostParticlesGl() { glDeleteBuffers(1, &buffer); }
};

// The particles from the host's own buffer draw the same frame, bit for bit,
// as the same particles handed over from the CPU (both with the GPU's
// anisotropic kernels, and both without them: the splat's spheres).
TEST_F(GlHostLayers, ParticlesFromTheHostsBufferDrawAsFromTheCpu) {
    const int W = 320, H = 180;
    const std::vector<glm::vec3>& positions = test::realFrame().positions;
    ASSERT_FALSE(positions.empty());
    setenv("MENISCUS_GL_HOST_ANISOTROPY", "0", 1);  // the CPU's particles: the GPU's kernels too (SetUp restores)
    auto gl = Renderer::createOnCurrentGlContext();
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    PlainHost plain(W, H);
    const HostLayers& host = plain.host;
    const HostFrameGl& frame = plain.frame;
    const std::vector<std::uint8_t>& rgba = plain.rgba;
    HostParticlesGl buffer(positions, 64);
    for (const bool anisotropic : {true, false}) {
        SCOPED_TRACE(anisotropic ? "anisotropic kernels" : "spheres");
        RenderSettings settings;
        settings.radiusM = test::realFrame().radius;
        settings.anisotropy.enabled = anisotropic;
        glBindFramebuffer(GL_FRAMEBUFFER, frame.framebuffer);
        auto st = gl->drawIntoHost(positions, settings, host);
        ASSERT_TRUE(st.ok()) << st.error().describe();
        const std::vector<std::uint8_t> fromCpu = frame.readTarget();
        std::vector<StageTime> times;
        st = gl->drawIntoHost(buffer.view, settings, host, &times);
        ASSERT_TRUE(st.ok()) << st.error().describe();
        const std::vector<std::uint8_t> fromBuffer = frame.readTarget();
        std::size_t differ = 0, liquid = 0;
        for (std::size_t i = 0; i < fromCpu.size(); i += 4) {
            differ += fromCpu[i] != fromBuffer[i] || fromCpu[i + 1] != fromBuffer[i + 1] ||
                      fromCpu[i + 2] != fromBuffer[i + 2];
            liquid += fromBuffer[i] != rgba[i] || fromBuffer[i + 1] != rgba[i + 1] || fromBuffer[i + 2] != rgba[i + 2];
        }
        EXPECT_EQ(differ, 0u);
        EXPECT_GT(liquid, std::size_t(W * H / 20));  // the liquid is there
        // The copy out of the host's buffer is timed as the GPU's first stage
        // (within the anisotropy, or on its own), and reported (Renderer::drawIntoHost's timings).
        const std::string first = anisotropic ? "anisotropy" : "host-particles";
        const auto device = std::find_if(times.begin(), times.end(),
                                         [](const StageTime& t) { return t.stage.rfind("host: ", 0) != 0; });
        ASSERT_NE(device, times.end());
        EXPECT_EQ(device->stage, first);
    }
}

// What cannot be read as described, and what needs the particles on the
// CPU, is refused with a message saying so.
TEST_F(GlHostLayers, AHostsBufferThatCannotBeReadIsRefused) {
    const int W = 64, H = 36;
    const std::vector<glm::vec3> positions = {{0.1f, 0.2f, 0.3f}, {0.2f, 0.2f, 0.3f}};
    auto gl = Renderer::createOnCurrentGlContext();
    ASSERT_TRUE(gl.ok()) << gl.error().describe();
    PlainHost plain(W, H);
    const HostLayers& host = plain.host;
    HostParticlesGl good(positions, 16);
    RenderSettings settings;
    settings.radiusM = 0.05f;
    auto refused = [&](HostParticleBuffer p, const RenderSettings& s, const char* says) {
        const Status st = gl->drawIntoHost(p, s, host);
        ASSERT_FALSE(st.ok()) << says;
        EXPECT_NE(st.error().describe().find(says), std::string::npos) << st.error().describe();
        EXPECT_NE(st.error().describe().find("the host's particle buffer"), std::string::npos) << st.error().describe();
    };
    HostParticleBuffer p = good.view;
    p.count = 3;  // one more than the buffer holds
    refused(p, settings, "do not fit in its 48 bytes");
    p = good.view;
    p.offsetBytes = 1u << 20;
    refused(p, settings, "do not fit");
    p = good.view;
    p.count = std::size_t(1) << 62;  // (count - 1) * stride would overflow
    refused(p, settings, "do not fit");
    p = good.view;
    p.strideBytes = 8;
    refused(p, settings, "12 bytes at least");
    p = good.view;
    p.offsetBytes = 2;
    refused(p, settings, "multiples of 4");
    p = good.view;
    p.buffer = good.buffer + 1000;
    refused(p, settings, "not a GL buffer");
    RenderSettings spray = settings;
    spray.spray.enabled = true;
    refused(good.view, spray, "the spray");
    RenderSettings noise = settings;
    noise.noise.enabled = true;
    refused(good.view, noise, "the surface noise");
    RenderSettings shadows = settings;
    shadows.shadows = ShadowMode::On;
    p = good.view;
    p.bounds = {};
    refused(p, shadows, "HostParticleBuffer::bounds");
    EXPECT_TRUE(gl->drawIntoHost(good.view, shadows, host).ok());  // with its box, shadows draw
    EXPECT_TRUE(gl->drawIntoHost(good.view, settings, host).ok());
}

}  // namespace
}  // namespace meniscus::gl_host_layers_test_local
