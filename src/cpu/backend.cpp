// The CPU reference backend: each stage method calls its src/cpu/ function on
// images kept per slot. Stage times are wall clock.
#include <chrono>

#include "core/backend.h"
#include "cpu/composite_fluids.h"
#include "cpu/filters.h"
#include "cpu/hole_fill.h"
#include "cpu/normals.h"
#include "cpu/raster_mesh.h"
#include "cpu/raycast.h"
#include "cpu/scene.h"
#include "cpu/shading.h"
#include "cpu/silhouette.h"
#include "cpu/splat.h"
#include "cpu/spray.h"
#include "cpu/surface_noise.h"
#include "cpu/velocity_map.h"
#include "cpu/thickness.h"
#include "cpu/upsample.h"

namespace meniscus {

namespace {

class CpuBackend final : public Backend {
public:
    std::string name() const override { return "cpu"; }

    Status beginFrame(std::span<const glm::vec3> positions, const FrameSettings& settings) override {
        positions_ = positions;
        s_ = settings;
        times_.clear();
        return okStatus();
    }

    void castScene(Slot color, Slot depth) override {
        if (!sceneValid_ || !(sceneCamera_ == s_.camera) || !(sceneStudio_ == s_.studio)) {
            scene_ = cpu::castScene(s_.camera, s_.studio);
            sceneCamera_ = s_.camera;
            sceneStudio_ = s_.studio;
            sceneValid_ = true;
        }
        // The slots name the cached layer itself (no per-frame copy).
        sceneColorSlot_ = int(color);
        sceneDepthSlot_ = int(depth);
    }

    void splat(Slot sceneDepth, Slot depth, Slot thickness) override {
        auto dt = cpu::splatDepthAndThickness(s_.camera, positions_, s_.radius, s_.thickness, &scalar(sceneDepth),
                                              s_.shapes);
        scalars_[int(depth)] = std::move(dt.depth);
        scalars_[int(thickness)] = std::move(dt.thickness);
    }

    void splatPartial(Slot sceneDepth, SplatPartial& partial) override {
        std::span<const glm::vec3> positions = positions_;
        std::span<const EllipsoidShape> shapes = s_.shapes;
        if (const auto& r = s_.splatRange) {  // this process's share of the whole frame
            positions = positions.subspan(r->begin, r->end - r->begin);
            if (!shapes.empty()) shapes = shapes.subspan(r->begin, r->end - r->begin);
        }
        partial = cpu::splatPartial(s_.camera, positions, s_.radius, s_.thickness, &scalar(sceneDepth), shapes);
    }

    void resolveSplat(SplatPartial& partial, Slot depth, Slot thickness) override {
        scalars_[int(thickness)] = cpu::resolveThickness(s_.camera, partial, s_.radius, s_.thickness);
        scalars_[int(depth)] = std::move(partial.depth);
    }

    void smooth(Slot in, Slot out) override {
        scalars_[int(out)] = cpu::smoothDepth(scalar(in), s_.camera, s_.radius, s_.filter);
    }

    void fillHoles(Slot sceneDepth, Slot depth, Slot thickness) override {
        cpu::fillHoles(s_.camera, s_.radius, s_.holeFill, &scalar(sceneDepth), scalars_[int(depth)],
                       scalars_[int(thickness)]);
    }

    void normals(Slot depth, Slot normal) override {
        vec3s_[int(normal)] = cpu::computeNormals(scalar(depth), s_.camera, s_.radius, defaults::kDepthJumpRadii);
    }

    void raycast(Slot sceneDepth, Slot raw, Slot depth, Slot normal) override {
        static const SphField kNoField;  // no field: no surface
        auto r = cpu::raycastSurface(s_.camera, s_.field ? *s_.field : kNoField, s_.raycast, s_.radius, scalar(raw),
                                     &scalar(sceneDepth));
        scalars_[int(depth)] = std::move(r.depth);
        vec3s_[int(normal)] = std::move(r.normal);
    }

    void rasterise(Slot sceneDepth, Slot depth, Slot normal) override {
        static const TriangleMesh kNoMesh;  // no mesh: no fluid
        auto r = cpu::rasteriseMesh(s_.camera, s_.mesh ? *s_.mesh : kNoMesh, &scalar(sceneDepth));
        scalars_[int(depth)] = std::move(r.depth);
        vec3s_[int(normal)] = std::move(r.normal);
    }

    void noise(Slot depth, Slot normal, Slot noise) override {
        scalars_[int(noise)] = cpu::splatNoise(s_.camera, positions_, s_.radius, scalar(depth), s_.noiseIdz,
                                               s_.noiseAmplitude, s_.noise);
        cpu::bumpNormals(s_.camera, s_.radius, scalar(depth), scalars_[int(noise)], s_.noise, vec3s_[int(normal)]);
    }

    void whitening(Slot depth, Slot whitening) override {
        scalars_[int(whitening)] =
            cpu::splatWhitening(s_.camera, positions_, s_.radius, scalar(depth), s_.whiteness, s_.whitening);
    }

    void shade(Slot sceneColor, Slot sceneDepth, Slot depth, Slot normal, Slot thickness, Slot noise,
               Slot whitening, Slot color, Slot emission, Slot transmit) override {
        // shadeAndComposite reads the scene as one layer: the cached cast when
        // the slots name it (always, in the pipeline), else a copy.
        const cpu::SceneLayer* scene = &scene_;
        cpu::SceneLayer copy;
        if (int(sceneColor) != sceneColorSlot_ || int(sceneDepth) != sceneDepthSlot_) {
            copy = {colorImage(sceneColor), scalar(sceneDepth)};
            scene = &copy;
        }
        cpu::LayerSplit split;
        if (emission != Slot::None) split = {&colors_[int(emission)], &colors_[int(transmit)]};
        colors_[int(color)] = cpu::shadeAndComposite(s_.camera, *scene, scalar(depth), vec3s_[int(normal)],
                                                     scalar(thickness), s_.shading,
                                                     s_.noise.enabled ? &scalar(noise) : nullptr, &s_.noise,
                                                     s_.whitening.enabled ? &scalar(whitening) : nullptr,
                                                     &s_.whitening, emission == Slot::None ? nullptr : &split,
                                                     s_.thickness.minRadii, s_.radius);
    }

    void setFluid(std::span<const glm::vec3> positions, const FluidSettings& fluid) override {
        positions_ = positions;
        s_.particles = fluid.particles;
        s_.shapes = fluid.shapes;
        s_.field = fluid.field;
        s_.shading = fluid.shading;
        s_.noiseIdz = fluid.noiseIdz;
        s_.noiseAmplitude = fluid.noiseAmplitude;
        s_.whiteness = fluid.whiteness;
    }

    void compositeFluids(std::span<const int> fluids, Slot sceneColor, Slot sceneDepth, Slot color, Slot depth,
                         Slot normal, Slot thickness, Slot fluidId) override {
        std::vector<cpu::FluidLayerImages> layers;
        for (std::size_t i = 0; i < fluids.size(); ++i) {
            const int l = int(i);
            layers.push_back({fluids[i], &scalar(layerSlot(l, LayerImage::Depth)),
                              &vec3s_[int(layerSlot(l, LayerImage::Normal))],
                              &scalar(layerSlot(l, LayerImage::Thickness)), &colorImage(layerSlot(l, LayerImage::Color)),
                              &colorImage(layerSlot(l, LayerImage::Emission)),
                              &colorImage(layerSlot(l, LayerImage::Transmit))});
        }
        cpu::Composited c = cpu::compositeFluids(layers, colorImage(sceneColor), &scalar(sceneDepth));
        colors_[int(color)] = std::move(c.color);
        scalars_[int(depth)] = std::move(c.depth);
        vec3s_[int(normal)] = std::move(c.normal);
        scalars_[int(thickness)] = std::move(c.thickness);
        scalars_[int(fluidId)] = std::move(c.fluid);
    }

    void silhouette(Slot sceneColor, Slot depth, Slot color, Slot silhouette) override {
        if (int(color) == sceneColorSlot_) {  // never fade the cached scene itself
            colors_[int(color)] = scene_.color;
            sceneColorSlot_ = -1;
        }
        scalars_[int(silhouette)] = cpu::reduceSilhouettes(s_.camera, scalar(depth), colorImage(sceneColor), s_.radius,
                                                           s_.silhouette, colors_[int(color)]);
    }

    void spray(Slot sceneDepth, Slot depth, Slot color, Slot spray) override {
        if (int(color) == sceneColorSlot_) {  // never paint over the cached scene
            colors_[int(color)] = scene_.color;
            sceneColorSlot_ = -1;
        }
        scalars_[int(spray)] = cpu::drawSpray(s_.camera, s_.sprayPositions, s_.sprayVelocities, s_.radius,
                                              scalar(depth), &scalar(sceneDepth), s_.spray,
                                              s_.shading.lightDirWorld, colors_[int(color)]);
    }

    void setCamera(const Camera& camera) override { s_.camera = camera; }

    void reduceSceneDepth(Slot fullSceneDepth, Slot lowSceneDepth) override {
        scalars_[int(lowSceneDepth)] =
            cpu::reduceSceneDepth(scalar(fullSceneDepth), s_.camera.width, s_.camera.height, s_.fluidDivisor);
    }

    void upsample(Slot lowDepth, Slot lowNormal, Slot lowThickness, Slot lowNoise, Slot sceneDepth, Slot depth,
                  Slot normal, Slot thickness, Slot noise, Slot coverage) override {
        cpu::Upsampled up = cpu::upsampleSurface(scalar(lowDepth), vec3s_[int(lowNormal)], scalar(lowThickness),
                                                 s_.noise.enabled ? &scalar(lowNoise) : nullptr, &scalar(sceneDepth),
                                                 s_.camera.width, s_.camera.height, s_.fluidDivisor, s_.upsampleJumpM);
        scalars_[int(depth)] = std::move(up.depth);
        vec3s_[int(normal)] = std::move(up.normal);
        scalars_[int(thickness)] = std::move(up.thickness);
        if (s_.noise.enabled) scalars_[int(noise)] = std::move(up.noise);
        scalars_[int(coverage)] = std::move(up.coverage);
    }

    void blendFluidEdges(Slot sceneColor, Slot depth, Slot coverage, Slot color, Slot emission,
                         Slot transmit) override {
        const bool split = emission != Slot::None;
        cpu::blendFluidEdges(scalar(depth), scalar(coverage), colorImage(sceneColor), colors_[int(color)],
                             split ? &colors_[int(emission)] : nullptr, split ? &colors_[int(transmit)] : nullptr);
    }

    Status stageStatus(const char*) override { return okStatus(); }

    void beginStage(const char* name) override {
        stage_ = name;
        t0_ = std::chrono::steady_clock::now();
    }
    void endStage() override {
        times_.push_back({stage_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count()});
    }
    std::vector<StageTime> stageTimes() override { return times_; }

    // Hand the frame's images over instead of copying them (tens of MB a
    // frame at 1280x720); the cached scene layer is copied, it is kept.
    Image<float> readScalar(Slot slot) override {
        return int(slot) == sceneDepthSlot_ ? scene_.depth : std::move(scalars_[int(slot)]);
    }
    Image<glm::vec3> readVec3(Slot slot) override { return std::move(vec3s_[int(slot)]); }
    Image<glm::vec4> readColor(Slot slot) override {
        return int(slot) == sceneColorSlot_ ? scene_.color : std::move(colors_[int(slot)]);
    }

    void writeColor(Slot slot, Image<glm::vec4> image) override {
        if (int(slot) == sceneColorSlot_) sceneColorSlot_ = -1;  // the slot no longer names the cached cast
        colors_[int(slot)] = std::move(image);
    }
    Status present(Slot, int, int, int) override {
        return makeError("", "the CPU backend cannot draw into a window (the viewer needs the GL backend)");
    }

private:
    const Image<float>& scalar(Slot s) const { return int(s) == sceneDepthSlot_ ? scene_.depth : scalars_[int(s)]; }
    const Image<glm::vec4>& colorImage(Slot s) const {
        return int(s) == sceneColorSlot_ ? scene_.color : colors_[int(s)];
    }

    std::span<const glm::vec3> positions_;
    FrameSettings s_;
    Image<float> scalars_[kSlotCount];
    Image<glm::vec3> vec3s_[kSlotCount];
    Image<glm::vec4> colors_[kSlotCount];
    // The last scene cast, kept while camera and studio stay the same.
    bool sceneValid_ = false;
    Camera sceneCamera_;
    shared::Studio sceneStudio_;
    cpu::SceneLayer scene_;
    int sceneColorSlot_ = -1, sceneDepthSlot_ = -1;
    std::string stage_;
    std::chrono::steady_clock::time_point t0_;
    std::vector<StageTime> times_;
};

}  // namespace

std::unique_ptr<Backend> makeCpuBackend() { return std::make_unique<CpuBackend>(); }

}  // namespace meniscus
