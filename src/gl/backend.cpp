// The GL backend (gl_backend.h): the frame, the images per slot, the scene's
// cache, timing, read-back and display. The stages are the drivers in their
// own files. Parameters reach every shader through the one FrameParams
// uniform block, uploaded in beginFrame (and when the camera or the fluid changes).
#include "gl/backend.h"

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gl/gl_backend.h"

namespace meniscus::gl {

namespace {

const char* glErrorName(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
        case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
        default: return "an unknown GL error";
    }
}

// Fault injection for the tests of stageStatus (tests/gl_backend_test.cpp):
// MENISCUS_GL_FAIL_STAGE=<stage> makes that stage issue one invalid GL call,
// so the real detection path sees a real GL error.
bool failStageForTest(const char* stage) {
    const char* v = std::getenv("MENISCUS_GL_FAIL_STAGE");
    return v && std::string_view(v) == stage;
}

std::string glString(GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
}

}  // namespace

GlBackend::GlBackend(std::unique_ptr<Context> ctx, Splat splat, std::optional<BufferFill> fill)
    : ctx_(std::move(ctx)),
      renderer_(ctx_ ? ctx_->renderer() : glString(GL_RENDERER)),
      hasResetStatus_(epoxy_gl_version() >= 45 || epoxy_has_gl_extension("GL_KHR_robustness")),
      splat_(std::move(splat)),
      fill_(std::move(fill)) {}

GlBackend::~GlBackend() {
    // GL objects are released with the context current.
    if (ctx_) (void)ctx_->makeCurrent();
}

void GlBackend::upload() {
    fp_ = packFrameParams(s_.camera, s_.radius, s_.filter, s_.thickness, s_.shading);
    block_.upload(fp_);
}

Status GlBackend::beginFrame(std::span<const glm::vec3> positions, const FrameSettings& settings) {
    if (ctx_)
        if (auto st = ctx_->makeCurrent(); !st) return st;
    // Errors left by GL calls before this frame (a viewer's own) are not
    // this frame's stages' to report.
    while (glGetError() != GL_NO_ERROR) {
    }
    s_ = settings;
    if (settings.hostLayers) {
        // Embedding: the host's framebuffer and viewport as they are now,
        // before any stage binds its own; present draws into them.
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &hostFramebuffer_);
        glGetIntegerv(GL_VIEWPORT, hostViewport_);
    }
    upload();
    stage_ = 0;
    return uploadParticles(positions);
}

Status GlBackend::uploadParticles(std::span<const glm::vec3> positions) {
    // Embedding with the host's own particle buffer: its positions gathered
    // on the GPU into the buffer the next pass reads (the anisotropy's, or
    // the splat's), nothing uploaded from the host.
    const HostParticleBuffer* fromHost = s_.hostParticles;
    if (fromHost) {
        if (auto st = HostParticleGather::check(*fromHost); !st) return st;
        if (!hostParticles_) {
            auto g = HostParticleGather::create();
            if (!g) return g.error();
            hostParticles_ = std::move(*g);
        }
    }
    if (!s_.deviceAnisotropy) {
        if (!fromHost) {
            splat_.uploadParticles(positions, s_.shapes);
            return okStatus();
        }
        if (s_.timed) beginStage("host-particles");
        hostParticles_->run(*fromHost, splat_.particleBuffer());
        splat_.useDeviceParticles(GLuint(fromHost->count));
        if (s_.timed) endStage();
        return stageStatus("host-particles");
    }
    if (!anisotropy_) {
        auto a = Anisotropy::create();
        if (!a) return a.error();
        anisotropy_ = std::move(*a);
    }
    if (s_.timed) beginStage("anisotropy");
    GLuint count = GLuint(positions.size());
    if (fromHost) {
        hostParticles_->run(*fromHost, anisotropy_->positionBuffer());
        count = GLuint(fromHost->count);
        anisotropy_->runOnDevice(count, s_.radius, *s_.deviceAnisotropy, s_.deviceRadii, s_.deviceShapeScale,
                                 splat_.particleBuffer(), splat_.shapeBuffer());
    } else {
        anisotropy_->run(positions, s_.radius, *s_.deviceAnisotropy, s_.deviceRadii, s_.deviceShapeScale,
                         splat_.particleBuffer(), splat_.shapeBuffer());
    }
    splat_.useDeviceShapes(count);
    if (s_.timed) endStage();
    return stageStatus("anisotropy");
}

void GlBackend::setFluid(std::span<const glm::vec3> positions, const FluidSettings& fluid) {
    s_.useFluid(fluid);
    upload();
    splat_.uploadParticles(positions, fluid.shapes);  // several fluids: the shapes come made
}

void GlBackend::setCamera(const Camera& camera) {
    s_.camera = camera;
    upload();
}

bool GlBackend::sceneCached(Slot color, Slot depth) const {
    const shared::EnvironmentMap& e = s_.environment;
    const bool sameEnv = sceneEnv_.texels == e.texels && sceneEnv_.width == e.width && sceneEnv_.height == e.height &&
                         sceneEnv_.rotation == e.rotation && sceneEnv_.intensity == e.intensity;
    return sceneValid_ && sameEnv && sceneCamera_ == s_.camera && sceneStudio_ == s_.studio &&
           sceneBackdrop_ == s_.backdrop && sceneSlots_ == std::pair(int(color), int(depth));
}

void GlBackend::sceneCast(Slot color, Slot depth) {
    sceneValid_ = true;
    sceneCamera_ = s_.camera;
    sceneStudio_ = s_.studio;
    sceneEnv_ = s_.environment;
    sceneEnvImage_ = s_.environmentImage;
    sceneBackdrop_ = s_.backdrop;
    sceneSlots_ = {int(color), int(depth)};
}

// A GL error since the last check, out of GPU memory among them, or a lost
// context (GL 4.5 / KHR_robustness reset status) fails the stage. glGetError
// does not wait for the GPU, so every frame checks.
Status GlBackend::stageStatus(const char* stage) {
    if (failStageForTest(stage)) glBindBuffer(GLenum(0xFFFF), 0);
    if (hasResetStatus_) {
        const GLenum reset = glGetGraphicsResetStatus();
        if (reset != GL_NO_ERROR)
            return makeError("", std::string("GL stage '") + stage + "': the GL context was lost (" +
                                     (reset == GL_GUILTY_CONTEXT_RESET ? "reset caused by this context"
                                                                       : "reset by the driver or another context") +
                                     "); create a new renderer");
    }
    GLenum first = glGetError();
    if (first == GL_NO_ERROR) return okStatus();
    int more = 0;
    for (GLenum e = glGetError(); e != GL_NO_ERROR && more < 64; e = glGetError()) ++more;
    std::string what = std::string("GL stage '") + stage + "' failed: " + glErrorName(first);
    if (first == GL_OUT_OF_MEMORY) what += " (out of GPU memory: try a smaller image)";
    else if (first == GL_CONTEXT_LOST) what += " (the GL context was lost; create a new renderer)";
    if (more) what += " and " + std::to_string(more) + " more GL error(s)";
    return makeError("", what);
}

// Each stage gets a GL_TIME_ELAPSED query and, after a glFinish, its wall
// time: llvmpipe answers timer queries with ~0 (it runs the work on the CPU
// outside the query's window), so when the queries of a frame sum to under
// 1% of the wall times, the wall times are reported instead. Brackets are
// only made when timings are asked for, so untimed frames never wait.
void GlBackend::beginStage(const char* name) {
    if (stage_ >= timers_.size()) timers_.push_back({makeQuery(), {}, 0.0, {}});
    Timer& t = timers_[stage_];
    t.name = name;
    glFinish();
    t.t0 = std::chrono::steady_clock::now();
    glBeginQuery(GL_TIME_ELAPSED, t.query.id());
}

void GlBackend::endStage() {
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    Timer& t = timers_[stage_];
    t.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t.t0).count();
    ++stage_;
}

std::vector<StageTime> GlBackend::stageTimes() {
    std::vector<StageTime> gpu, wall;
    double gpuSum = 0.0, wallSum = 0.0;
    for (std::size_t k = 0; k < stage_; ++k) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(timers_[k].query.id(), GL_QUERY_RESULT, &ns);
        // The GPU's time lies inside the wall time (two glFinish calls bound
        // it); longer is no measurement (llvmpipe's timer around a draw call
        // gives a timestamp), so the wall time stands for it.
        const double gpuMs = double(ns) * 1e-6;
        gpu.push_back({timers_[k].name, gpuMs <= 1.5 * timers_[k].wallMs + 1.0 ? gpuMs : timers_[k].wallMs});
        wall.push_back({timers_[k].name, timers_[k].wallMs});
        gpuSum += gpu.back().ms;
        wallSum += timers_[k].wallMs;
    }
    return gpuSum > 0.01 * wallSum ? gpu : wall;
}

void GlBackend::writeColor(Slot slot, Image<glm::vec4> image) {
    const auto fills = bufferFills();
    forget(slot);
    img(slot).upload(image);
}

Status GlBackend::present(Slot color, const PresentTarget& target) {
    const auto fills = bufferFills();
    if (ctx_) return makeError("", "a headless GL backend has no window or host framebuffer to draw into "
                                   "(Renderer::createOnCurrentGlContext makes one that has)");
    if (!presenter_) {  // compiled on first use: headless backends never need it
        auto p = Presenter::create();
        if (!p) return p.error();
        presenter_ = std::move(*p);
    }
    presenter_->draw(img(color), target, target.hostFramebuffer ? GLuint(hostFramebuffer_) : 0u);
    if (target.hostFramebuffer) glViewport(hostViewport_[0], hostViewport_[1], hostViewport_[2], hostViewport_[3]);
    return okStatus();
}

namespace {

// The backend on the current context; `ctx` is that context when the backend
// owns it, else null. The stages' own programs are made by their drivers'
// prepare (the stage list's prepareStages) before the first frame.
Result<std::unique_ptr<Backend>> makeOnCurrent(std::unique_ptr<Context> ctx) {
    auto splat = Splat::create();
    if (!splat) return splat.error();
    std::optional<BufferFill> fill;
    if (useShaderFills(ctx ? ctx->renderer() : glString(GL_RENDERER))) {
        auto f = BufferFill::create();
        if (!f) return f.error();
        fill = std::move(*f);
    }
    return std::unique_ptr<Backend>(std::make_unique<GlBackend>(std::move(ctx), std::move(*splat), std::move(fill)));
}

}  // namespace

Result<std::unique_ptr<Backend>> makeGlBackend() {
    auto ctx = Context::createHeadless();
    if (!ctx) return ctx.error();
    return makeOnCurrent(std::move(*ctx));
}

Result<std::unique_ptr<Backend>> makeGlBackendOnCurrentContext() {
    // epoxy_gl_version() reads GL_VERSION: 0 when no context is current.
    if (epoxy_gl_version() < 43) {
        const std::string version = glString(GL_VERSION);
        return makeError("", "the current OpenGL context is not version 4.3 or later (GL_VERSION: " +
                                 (version.empty() ? std::string("none, no context is current") : version) + ")");
    }
    return makeOnCurrent(nullptr);
}

}  // namespace meniscus::gl
