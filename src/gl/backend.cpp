// The GL backend: each stage method runs its src/gl/ stage class on GPU
// images kept per slot. Parameters reach every shader through the one
// FrameParams uniform block, uploaded in beginFrame. Stage times come from
// GL_TIME_ELAPSED queries, one per stage bracket. The backend runs on its own
// headless context or on one already current (a viewer's window), where it
// can also present its colour.
#include "gl/backend.h"

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <optional>
#include <type_traits>
#include <variant>
#include <utility>
#include <vector>

#include "gl/buffer_fill.h"
#include "gl/composite_fluids.h"
#include "gl/context.h"
#include "gl/filter_curvature_flow.h"
#include "gl/filter_narrow_range.h"
#include "gl/filter_separable.h"
#include "gl/gpu_image.h"
#include "gl/hole_fill.h"
#include "gl/normals.h"
#include "gl/present.h"
#include "gl/raster_mesh.h"
#include "gl/raycast.h"
#include "gl/scene.h"
#include "gl/shading.h"
#include "gl/silhouette.h"
#include "gl/splat.h"
#include "gl/spray.h"
#include "gl/surface_noise.h"
#include "gl/thickness_lowres.h"
#include "gl/uniforms.h"
#include "gl/upsample.h"
#include "shared/thickness.h"

namespace meniscus::gl {

namespace {

struct Stages {
    Splat splat;
    SeparableFilters separable;
    CurvatureFlow curvatureFlow;
    NarrowRange narrowRange;
    SceneCaster scene;
    Normals normals;
    Shading shading;
    LowResThickness lowResThickness;
    MeshRasteriser meshRasteriser;
    Raycast raycast;
    HoleFill holeFill;
    SurfaceNoise surfaceNoise;
    SilhouetteReduction silhouetteReduction;
    SprayDrops sprayDrops;
    Upsampling upsampling;
    FluidCompositor fluidCompositor;
};

template <class T>
Status take(Result<T>&& r, T& out) {
    if (!r) return r.error();
    out = std::move(*r);
    return okStatus();
}

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

class GlBackend final : public Backend {
public:
    // `ctx` null: the context current at construction, owned by someone else
    // (a gl::Window), which keeps it current while the backend is used.
    // `fill`: the shader fills and copies (gl/buffer_fill.h), or none for the driver's.
    GlBackend(std::unique_ptr<Context> ctx, Stages stages, std::optional<BufferFill> fill)
        : ctx_(std::move(ctx)),
          renderer_(ctx_ ? ctx_->renderer() : glString(GL_RENDERER)),
          hasResetStatus_(epoxy_gl_version() >= 45 || epoxy_has_gl_extension("GL_KHR_robustness")),
          st_(std::move(stages)),
          fill_(std::move(fill)) {}
    ~GlBackend() override {
        // GL objects are released with the context current.
        if (ctx_) (void)ctx_->makeCurrent();
    }

    std::string name() const override { return "gl (" + renderer_ + ")"; }

    Status beginFrame(std::span<const glm::vec3> positions, const FrameSettings& settings) override {
        if (ctx_)
            if (auto st = ctx_->makeCurrent(); !st) return st;
        // Errors left by GL calls before this frame (a viewer's own) are not
        // this frame's stages' to report.
        while (glGetError() != GL_NO_ERROR) {
        }
        s_ = settings;
        fp_ = packFrameParams(settings.camera, settings.radius, settings.filter, settings.thickness, settings.shading);
        block_.upload(fp_);
        st_.splat.uploadParticles(positions, settings.shapes);
        stage_ = 0;
        return okStatus();
    }

    void castScene(Slot color, Slot depth) override {
        const auto fills = bufferFills();
        const bool same = sceneValid_ && sceneCamera_ == s_.camera && sceneStudio_ == s_.studio &&
                          sceneSlots_ == std::pair(int(color), int(depth));
        if (same) return;
        st_.scene.run(fp_, s_.studio, img(color), img(depth));
        sceneValid_ = true;
        sceneCamera_ = s_.camera;
        sceneStudio_ = s_.studio;
        sceneSlots_ = {int(color), int(depth)};
    }

    void splat(Slot sceneDepth, Slot depth, Slot thickness) override {
        const auto fills = bufferFills();
        forget(depth);
        forget(thickness);
        // The thickness grid: 1, 2 or 4 pixels per block side.
        const int d = shared::thicknessDivisor(fp_.thicknessResolutionDivisor);
        if (d == 1) {
            st_.splat.run(fp_, &img(sceneDepth), img(depth), &img(thickness));
            st_.separable.blurThickness(fp_, img(depth), img(thickness));
        } else {
            st_.splat.run(fp_, &img(sceneDepth), img(depth), nullptr);
            st_.lowResThickness.run(fp_, st_.splat, st_.separable, &img(sceneDepth), img(depth), d, img(thickness));
        }
    }

    // Sort-last: the splat's depth and fixed-point sums read back for the
    // compositor, and the combination uploaded and resolved as splat() does.
    void splatPartial(Slot sceneDepth, SplatPartial& partial) override {
        const auto fills = bufferFills();
        const int d = shared::thicknessDivisor(fp_.thicknessResolutionDivisor);
        if (d == 1) {
            st_.splat.runPartial(fp_, &img(sceneDepth), partialDepth_, partialChords_);
        } else {
            st_.splat.run(fp_, &img(sceneDepth), partialDepth_, nullptr);
            st_.lowResThickness.chords(fp_, st_.splat, &img(sceneDepth), d, partialChords_);
        }
        partial.depth = download<float>(partialDepth_);
        partial.chords = download<std::uint32_t>(partialChords_);
    }

    void resolveSplat(SplatPartial& partial, Slot depth, Slot thickness) override {
        const auto fills = bufferFills();
        forget(depth);
        forget(thickness);
        img(depth).upload(partial.depth);
        const int d = shared::thicknessDivisor(fp_.thicknessResolutionDivisor);
        if (d == 1) {
            img(thickness).upload(partial.chords);  // resolved in place, as splat() leaves it
            st_.splat.resolveChords(fp_, img(thickness));
            st_.separable.blurThickness(fp_, img(depth), img(thickness));
        } else {
            partialChords_.upload(partial.chords);
            st_.lowResThickness.resolve(fp_, st_.splat, st_.separable, img(depth), d, partialChords_, img(thickness));
        }
    }

    void smooth(Slot in, Slot out) override {
        const auto fills = bufferFills();
        forget(out);
        GpuImage& src = img(in);
        GpuImage& dst = img(out);
        // The stage follows the filter variant itself: a filter added to
        // FilterParams without a GL stage does not compile.
        std::visit(
            [&](const auto& q) {
                using Q = std::decay_t<decltype(q)>;
                if constexpr (std::is_same_v<Q, NoFilter>) {
                    dst.copyFrom(src);
                    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
                } else if constexpr (std::is_same_v<Q, GaussianParams>) {
                    st_.separable.run(fp_, SeparableKind::Gaussian, src, dst);
                } else if constexpr (std::is_same_v<Q, BilateralParams>) {
                    st_.separable.run(fp_, SeparableKind::Bilateral, src, dst);
                } else if constexpr (std::is_same_v<Q, BinomialParams>) {
                    st_.separable.run(fp_, SeparableKind::Binomial, src, dst);
                } else if constexpr (std::is_same_v<Q, CurvatureFlowParams>) {
                    st_.curvatureFlow.run(fp_, src, dst);
                } else if constexpr (std::is_same_v<Q, NarrowRangeParams>) {
                    st_.narrowRange.run(fp_, src, dst);
                } else {
                    static_assert(sizeof(Q) == 0, "a filter without a GL stage");
                }
            },
            s_.filter);
    }

    void fillHoles(Slot sceneDepth, Slot depth, Slot thickness) override {
        const auto fills = bufferFills();
        forget(depth);
        forget(thickness);
        st_.holeFill.run(fp_, s_.holeFill, &img(sceneDepth), img(depth), img(thickness));
    }

    void normals(Slot depth, Slot normal) override {
        const auto fills = bufferFills();
        forget(normal);
        st_.normals.run(fp_, img(depth), img(normal));
    }

    void raycast(Slot sceneDepth, Slot raw, Slot depth, Slot normal) override {
        const auto fills = bufferFills();
        forget(depth);
        forget(normal);
        st_.raycast.run(fp_, s_.field, s_.raycast, img(raw), &img(sceneDepth), img(depth), img(normal));
    }

    void rasterise(Slot sceneDepth, Slot depth, Slot normal) override {
        const auto fills = bufferFills();
        forget(depth);
        forget(normal);
        static const TriangleMesh kNoMesh;  // no mesh: no fluid
        st_.meshRasteriser.run(fp_, s_.mesh ? *s_.mesh : kNoMesh, &img(sceneDepth), img(depth), img(normal));
    }

    void noise(Slot depth, Slot normal, Slot noise) override {
        const auto fills = bufferFills();
        forget(normal);
        forget(noise);
        st_.surfaceNoise.run(fp_, s_.camera, s_.noise, st_.splat.particleBuffer(), st_.splat.particleCount(),
                             s_.noiseIdz, s_.noiseAmplitude, img(depth), img(normal), img(noise));
    }

    void whitening(Slot depth, Slot whitening) override {
        const auto fills = bufferFills();
        forget(whitening);
        st_.surfaceNoise.runWhitening(fp_, s_.camera, s_.whitening, st_.splat.particleBuffer(),
                                      st_.splat.particleCount(), s_.whiteness, img(depth), img(whitening));
    }

    void shade(Slot sceneColor, Slot sceneDepth, Slot depth, Slot normal, Slot thickness, Slot noise,
               Slot whitening, Slot color, Slot emission, Slot transmit) override {
        const auto fills = bufferFills();
        forget(color);
        const bool split = emission != Slot::None;
        // Foam only with the noise on (its slot then holds this frame's N),
        // white water only with the whitening on (likewise its map).
        st_.shading.run(fp_, img(sceneColor), img(sceneDepth), img(depth), img(normal), img(thickness), img(color),
                        s_.noise.enabled ? &img(noise) : nullptr, &s_.noise,
                        s_.whitening.enabled ? &img(whitening) : nullptr, &s_.whitening,
                        split ? &img(emission) : nullptr, split ? &img(transmit) : nullptr);
    }

    void setFluid(std::span<const glm::vec3> positions, const FluidSettings& fluid) override {
        s_.particles = fluid.particles;
        s_.field = fluid.field;
        s_.shading = fluid.shading;
        s_.noiseIdz = fluid.noiseIdz;
        s_.noiseAmplitude = fluid.noiseAmplitude;
        s_.whiteness = fluid.whiteness;
        fp_ = packFrameParams(s_.camera, s_.radius, s_.filter, s_.thickness, s_.shading);
        block_.upload(fp_);
        st_.splat.uploadParticles(positions, fluid.shapes);
    }

    void compositeFluids(std::span<const int> fluids, Slot sceneColor, Slot sceneDepth, Slot color, Slot depth,
                         Slot normal, Slot thickness, Slot fluidId) override {
        const auto fills = bufferFills();
        for (Slot out : {color, depth, normal, thickness, fluidId}) forget(out);
        std::vector<FluidLayerGpu> layers;
        for (std::size_t i = 0; i < fluids.size(); ++i) {
            const int l = int(i);
            layers.push_back({fluids[i], &img(layerSlot(l, LayerImage::Depth)), &img(layerSlot(l, LayerImage::Normal)),
                              &img(layerSlot(l, LayerImage::Thickness)), &img(layerSlot(l, LayerImage::Color)),
                              &img(layerSlot(l, LayerImage::Emission)), &img(layerSlot(l, LayerImage::Transmit))});
        }
        st_.fluidCompositor.run(layers, img(sceneColor), img(sceneDepth), img(color), img(depth), img(normal),
                                img(thickness), img(fluidId));
    }

    void silhouette(Slot sceneColor, Slot depth, Slot color, Slot silhouette) override {
        const auto fills = bufferFills();
        // Faded in place: a colour slot that held the cached scene no longer
        // does (the next cast redraws it), as the CPU copies its cached scene
        // out before fading, never the scene itself.
        forget(color);
        forget(silhouette);
        st_.silhouetteReduction.run(s_.camera, img(depth), img(sceneColor), s_.radius, s_.silhouette, img(color),
                                    img(silhouette));
    }

    void spray(Slot sceneDepth, Slot depth, Slot color, Slot spray) override {
        const auto fills = bufferFills();
        // Drawn over the colour in place: a colour slot that held the cached
        // scene no longer does (the next cast redraws it), as the CPU copies
        // its cached scene out before painting, never over it.
        forget(color);
        forget(spray);
        st_.sprayDrops.run(s_.camera, s_.sprayPositions, s_.sprayVelocities, s_.radius, s_.spray,
                           s_.shading.lightDirWorld, img(depth), &img(sceneDepth), img(color), img(spray));
    }

    // A GL error since the last check, out of GPU memory among them, or a
    // lost context (GL 4.5 / KHR_robustness reset status) fails the stage.
    // glGetError does not wait for the GPU, so every frame checks.
    void setCamera(const Camera& camera) override {
        s_.camera = camera;
        fp_ = packFrameParams(s_.camera, s_.radius, s_.filter, s_.thickness, s_.shading);
        block_.upload(fp_);
    }

    void reduceSceneDepth(Slot fullSceneDepth, Slot lowSceneDepth) override {
        const auto fills = bufferFills();
        forget(lowSceneDepth);
        st_.upsampling.reduceSceneDepth(img(fullSceneDepth), s_.camera.width, s_.camera.height, s_.fluidDivisor,
                                        img(lowSceneDepth));
    }

    void upsample(Slot lowDepth, Slot lowNormal, Slot lowThickness, Slot lowNoise, Slot sceneDepth, Slot depth,
                  Slot normal, Slot thickness, Slot noise, Slot coverage) override {
        const auto fills = bufferFills();
        for (Slot out : {depth, normal, thickness, noise, coverage}) forget(out);
        st_.upsampling.upsample(img(lowDepth), img(lowNormal), img(lowThickness),
                                s_.noise.enabled ? &img(lowNoise) : nullptr, &img(sceneDepth), s_.camera.width,
                                s_.camera.height, s_.fluidDivisor, s_.upsampleJumpM, img(depth), img(normal),
                                img(thickness), s_.noise.enabled ? &img(noise) : nullptr, img(coverage));
    }

    void blendFluidEdges(Slot sceneColor, Slot depth, Slot coverage, Slot color, Slot emission,
                         Slot transmit) override {
        const auto fills = bufferFills();
        const bool split = emission != Slot::None;
        st_.upsampling.blendEdges(img(depth), img(coverage), img(sceneColor), img(color),
                                  split ? &img(emission) : nullptr, split ? &img(transmit) : nullptr);
    }

    Status stageStatus(const char* stage) override {
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
    // 1% of the wall times, the wall times are reported instead. Brackets are only made when timings
    // are asked for, so untimed frames never wait.
    void beginStage(const char* name) override {
        if (stage_ >= timers_.size()) timers_.push_back({makeQuery(), {}, 0.0, {}});
        Timer& t = timers_[stage_];
        t.name = name;
        glFinish();
        t.t0 = std::chrono::steady_clock::now();
        glBeginQuery(GL_TIME_ELAPSED, t.query.id());
    }
    void endStage() override {
        glEndQuery(GL_TIME_ELAPSED);
        glFinish();
        Timer& t = timers_[stage_];
        t.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t.t0).count();
        ++stage_;
    }
    std::vector<StageTime> stageTimes() override {
        std::vector<StageTime> gpu, wall;
        double gpuSum = 0.0, wallSum = 0.0;
        for (std::size_t k = 0; k < stage_; ++k) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(timers_[k].query.id(), GL_QUERY_RESULT, &ns);
            gpu.push_back({timers_[k].name, double(ns) * 1e-6});
            wall.push_back({timers_[k].name, timers_[k].wallMs});
            gpuSum += double(ns) * 1e-6;
            wallSum += timers_[k].wallMs;
        }
        return gpuSum > 0.01 * wallSum ? gpu : wall;
    }

    Image<float> readScalar(Slot slot) override { return download<float>(slot); }
    Image<glm::vec3> readVec3(Slot slot) override { return download<glm::vec3>(slot); }
    Image<glm::vec4> readColor(Slot slot) override { return download<glm::vec4>(slot); }

    void writeColor(Slot slot, Image<glm::vec4> image) override {
        const auto fills = bufferFills();
        forget(slot);
        img(slot).upload(image);
    }
    Status present(Slot color, int framebufferWidth, int framebufferHeight, int left) override {
        const auto fills = bufferFills();
        if (ctx_) return makeError("", "a headless GL backend has no window to draw into");
        if (!presenter_) {  // compiled on first use: headless backends never need it
            auto p = Presenter::create();
            if (!p) return p.error();
            presenter_ = std::move(*p);
        }
        presenter_->draw(img(color), framebufferWidth, framebufferHeight, left);
        return okStatus();
    }

private:
    GpuImage& img(Slot s) { return images_[int(s)]; }
    // A slot read back. With shader fills (a hardware GPU) through a staging
    // buffer: NVIDIA's driver moves a buffer it sees read back every frame to
    // host memory, where the stage writing it then writes over PCIe (the
    // shading's colour: 2.3 ms at 1920x1080 on an H200); the staging copy
    // takes that move instead. MENISCUS_GL_STAGED_READBACK=0|1 overrides.
    template <class T>
    Image<T> download(Slot slot) {
        return download<T>(img(slot));
    }
    template <class T>
    Image<T> download(const GpuImage& image) {
        static const char* env = std::getenv("MENISCUS_GL_STAGED_READBACK");
        const bool staged = env && *env ? *env == '1' : fill_.has_value();
        if (!staged) return image.download<T>();
        {
            const auto fills = bufferFills();
            staging_.copyFrom(image);
        }
        return staging_.download<T>();
    }
    // Installs this backend's shader fills for the Buffer calls of one method.
    ScopedBufferFill bufferFills() const { return ScopedBufferFill(fill_ ? &*fill_ : nullptr); }
    // A stage writing a slot that held the cached scene invalidates the cache.
    void forget(Slot s) {
        if (sceneValid_ && (int(s) == sceneSlots_.first || int(s) == sceneSlots_.second)) sceneValid_ = false;
    }

    struct Timer {
        Query query;
        std::string name;
        double wallMs = 0.0;
        std::chrono::steady_clock::time_point t0;
    };

    std::unique_ptr<Context> ctx_;  // first: destroyed last; null on a window's context
    std::string renderer_;          // GL_RENDERER
    bool hasResetStatus_;           // glGetGraphicsResetStatus exists (asked once, not per stage)
    Stages st_;
    std::optional<BufferFill> fill_;  // shader fills and copies; none: the driver's
    std::optional<Presenter> presenter_;
    FrameParamsBlock block_;
    FrameParams fp_{};
    FrameSettings s_;
    GpuImage images_[kSlotCount];
    GpuImage staging_;  // read-back copies (download)
    GpuImage partialDepth_, partialChords_;  // sort-last: this share's splat before it is read back
    bool sceneValid_ = false;
    Camera sceneCamera_;
    shared::Studio sceneStudio_;
    std::pair<int, int> sceneSlots_{-1, -1};
    std::vector<Timer> timers_;
    std::size_t stage_ = 0;
};

// Compiles every stage on the current context; `ctx` is that context when the
// backend owns it, else null.
Result<std::unique_ptr<Backend>> makeOnCurrent(std::unique_ptr<Context> ctx) {
    Stages s;
    for (Status st : {take(Splat::create(), s.splat), take(SeparableFilters::create(), s.separable),
                      take(CurvatureFlow::create(), s.curvatureFlow), take(NarrowRange::create(), s.narrowRange),
                      take(SceneCaster::create(), s.scene), take(Normals::create(), s.normals),
                      take(Shading::create(), s.shading), take(LowResThickness::create(), s.lowResThickness),
                      take(MeshRasteriser::create(), s.meshRasteriser), take(Raycast::create(), s.raycast),
                      take(HoleFill::create(), s.holeFill),
                      take(SurfaceNoise::create(), s.surfaceNoise),
                      take(SilhouetteReduction::create(), s.silhouetteReduction),
                      take(SprayDrops::create(), s.sprayDrops), take(Upsampling::create(), s.upsampling),
                      take(FluidCompositor::create(), s.fluidCompositor)})
        if (!st) return st.error();
    std::optional<BufferFill> fill;
    if (useShaderFills(ctx ? ctx->renderer() : glString(GL_RENDERER))) {
        auto f = BufferFill::create();
        if (!f) return f.error();
        fill = std::move(*f);
    }
    return std::unique_ptr<Backend>(std::make_unique<GlBackend>(std::move(ctx), std::move(s), std::move(fill)));
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
