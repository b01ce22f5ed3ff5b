// The GL backend: the frame's particles (uploaded once, the splat's buffer)
// and settings (the one FrameParams uniform block every shader reads), GPU
// images kept per slot, and each stage's GL objects, made once by its driver
// (its StageDriver in src/gl/<stage>.cpp, named by the stage list) and kept
// here by type. Stage times come from GL_TIME_ELAPSED queries, one per stage
// bracket. The backend runs on its own headless context or on one already
// current (a viewer's window), where it can also present its colour.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <typeindex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/backend.h"
#include "gl/anisotropy.h"
#include "gl/buffer_fill.h"
#include "gl/context.h"
#include "gl/environment.h"
#include "gl/gpu_image.h"
#include "gl/host_layers.h"
#include "gl/objects.h"
#include "gl/present.h"
#include "gl/splat.h"
#include "gl/uniforms.h"

namespace meniscus::gl {

class GlBackend final : public Backend {
public:
    // `ctx` null: the context current at construction, owned by someone else
    // (a gl::Window), which keeps it current while the backend is used.
    // `splat`: the particles' buffer and the splat's programs. `fill`: the
    // shader fills and copies (gl/buffer_fill.h), or none for the driver's.
    GlBackend(std::unique_ptr<Context> ctx, Splat splat, std::optional<BufferFill> fill);
    ~GlBackend() override;

    // The GL backend under a stage driver's Backend&.
    static GlBackend& of(Backend& b) { return static_cast<GlBackend&>(b); }

    std::string name() const override { return "gl (" + renderer_ + ")"; }
    BackendKind kind() const override { return BackendKind::Gl; }
    Status beginFrame(std::span<const glm::vec3> positions, const FrameSettings& settings) override;
    void setFluid(std::span<const glm::vec3> positions, const FluidSettings& fluid) override;
    void setCamera(const Camera& camera) override;
    Status stageStatus(const char* stage) override;
    void beginStage(const char* name) override;
    void endStage() override;
    std::vector<StageTime> stageTimes() override;
    Image<float> readScalar(Slot slot) override { return download<float>(img(slot)); }
    Image<glm::vec3> readVec3(Slot slot) override { return download<glm::vec3>(img(slot)); }
    Image<glm::vec4> readColor(Slot slot) override { return download<glm::vec4>(img(slot)); }
    void writeColor(Slot slot, Image<glm::vec4> image) override;
    Status present(Slot color, const PresentTarget& target) override;

    // ---- For the stage drivers.
    // The frame's settings (the current fluid's, at the current camera) and
    // their packed uniform block.
    const FrameSettings& frame() const { return s_; }
    const FrameParams& params() const { return fp_; }
    // The particles' buffer (the current fluid's) and the splat's programs.
    Splat& particles() { return splat_; }
    GpuImage& img(Slot s) { return images_[int(s)]; }
    // Sort-last: this share's splat before it is read back.
    GpuImage& partialDepth() { return partialDepth_; }
    GpuImage& partialChords() { return partialChords_; }
    // An image read back to the host (through a staging copy where the
    // driver needs one: see download's definition).
    template <class T>
    Image<T> download(const GpuImage& image);
    // Installs this backend's shader fills for the Buffer calls of one stage.
    ScopedBufferFill bufferFills() const { return ScopedBufferFill(fill_ ? &*fill_ : nullptr); }
    // A stage writing a slot that held the cached scene invalidates the cache.
    void forget(Slot s) {
        if (sceneValid_ && (int(s) == sceneSlots_.first || int(s) == sceneSlots_.second)) sceneValid_ = false;
    }
    // Whether the scene cast into these slots is still valid (the same
    // camera, studio and slots as the last cast); sceneCast records a cast.
    bool sceneCached(Slot color, Slot depth) const;
    // The frame's environment map on the GPU (uploaded when it changes).
    const EnvironmentGpu& environment() {
        env_.update(s_.environment, s_.environmentImage);
        return env_;
    }
    void sceneCast(Slot color, Slot depth);

    // A stage's GL objects of type T (T::create(): its programs), made once
    // per backend by the stage driver's prepare; pass<T>() after that.
    template <class T>
    Status prepare() {
        std::shared_ptr<void>& p = passes_[std::type_index(typeid(T))];
        if (p) return okStatus();
        auto made = T::create();
        if (!made) return made.error();
        p = std::make_shared<T>(std::move(*made));
        return okStatus();
    }
    template <class T>
    T& pass() {
        return *static_cast<T*>(passes_.at(std::type_index(typeid(T))).get());
    }

private:
    struct Timer {
        Query query;
        std::string name;
        double wallMs = 0.0;
        std::chrono::steady_clock::time_point t0;
    };
    void upload();
    // The particles into the splat's buffer: uploaded with their shapes, or
    // with deviceAnisotropy their ellipsoids made here (timed as the
    // anisotropy stage when the frame is timed).
    Status uploadParticles(std::span<const glm::vec3> positions);

    std::unique_ptr<Context> ctx_;  // first: destroyed last; null on a window's context
    std::string renderer_;          // GL_RENDERER
    bool hasResetStatus_;           // glGetGraphicsResetStatus exists (asked once, not per stage)
    Splat splat_;
    std::optional<Anisotropy> anisotropy_;  // made on first use
    std::optional<HostParticleGather> hostParticles_;  // made on first use: particles from a host's buffer
    std::unordered_map<std::type_index, std::shared_ptr<void>> passes_;
    std::optional<BufferFill> fill_;  // shader fills and copies; none: the driver's
    std::optional<Presenter> presenter_;
    GLint hostFramebuffer_ = 0;            // embedding: the host's draw framebuffer when the frame began
    GLint hostViewport_[4] = {0, 0, 0, 0};  // and its viewport
    FrameParamsBlock block_;
    FrameParams fp_{};
    FrameSettings s_;
    GpuImage images_[kSlotCount];
    GpuImage staging_;                       // read-back copies (download)
    GpuImage partialDepth_, partialChords_;  // sort-last: this share's splat before it is read back
    bool sceneValid_ = false;
    Camera sceneCamera_;
    shared::Studio sceneStudio_;
    shared::EnvironmentMap sceneEnv_;  // the environment map of the cached cast
    std::shared_ptr<const EnvironmentImage> sceneEnvImage_;  // kept alive while cached (its address is the key)
    std::shared_ptr<const BackdropImage> sceneBackdrop_;  // the backdrop the cast is of, or null (the studio)
    EnvironmentGpu env_;
    std::pair<int, int> sceneSlots_{-1, -1};
    std::vector<Timer> timers_;
    std::size_t stage_ = 0;
};

// A GL stage driver's run (StageDriver::run) made of a function of the GL
// backend: the backend's buffer fills are installed for the stage around it.
template <void (*run)(GlBackend&, const StageIo&)>
void glRun(Backend& b, const StageIo& io) {
    GlBackend& g = GlBackend::of(b);
    const auto fills = g.bufferFills();
    run(g, io);
}

// A GL stage driver's prepare (StageDriver::prepare): the passes it runs,
// made once per backend; the first error.
template <class... Passes>
Status glPrepare(Backend& b) {
    GlBackend& g = GlBackend::of(b);
    Status st = okStatus();
    ((st = st ? g.prepare<Passes>() : st), ...);
    return st;
}

// A slot read back. With shader fills (a hardware GPU) through a staging
// buffer: NVIDIA's driver moves a buffer it sees read back every frame to
// host memory, where the stage writing it then writes over PCIe (the
// shading's colour: 2.3 ms at 1920x1080 on an H200); the staging copy takes
// that move instead. MENISCUS_GL_STAGED_READBACK=0|1 overrides.
template <class T>
Image<T> GlBackend::download(const GpuImage& image) {
    static const char* env = std::getenv("MENISCUS_GL_STAGED_READBACK");
    const bool staged = env && *env ? *env == '1' : fill_.has_value();
    if (!staged) return image.download<T>();
    {
        const auto fills = bufferFills();
        staging_.copyFrom(image);
    }
    return staging_.download<T>();
}

}  // namespace meniscus::gl
