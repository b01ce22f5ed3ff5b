// The CPU reference backend: the frame's particles and settings and the
// images kept per slot, which each stage's CPU driver (its StageDriver in
// src/cpu/<stage>.cpp, named by the stage list) reads and writes. Stage times
// are wall clock.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/backend.h"
#include "cpu/raster_mesh.h"
#include "cpu/scene.h"

namespace meniscus::cpu {

class CpuBackend final : public Backend {
public:
    // The CPU backend under a stage driver's Backend&.
    static CpuBackend& of(Backend& b) { return static_cast<CpuBackend&>(b); }

    std::string name() const override { return "cpu"; }
    BackendKind kind() const override { return BackendKind::Cpu; }
    Status beginFrame(std::span<const glm::vec3> positions, const FrameSettings& settings) override;
    void setFluid(std::span<const glm::vec3> positions, const FluidSettings& fluid) override;
    void setCamera(const Camera& camera) override { s_.camera = camera; }
    Status stageStatus(const char*) override { return okStatus(); }
    void beginStage(const char* name) override;
    void endStage() override;
    std::vector<StageTime> stageTimes() override { return times_; }
    Image<float> readScalar(Slot slot) override;
    Image<glm::vec3> readVec3(Slot slot) override { return std::move(vec3s_[int(slot)]); }
    Image<glm::vec4> readColor(Slot slot) override;
    void writeColor(Slot slot, Image<glm::vec4> image) override;
    Status present(Slot, const PresentTarget&) override;

    // ---- For the stage drivers.
    // The frame's settings (the current fluid's, at the current camera) and
    // the positions the splat reads (the current fluid's).
    const FrameSettings& frame() const { return s_; }
    std::span<const glm::vec3> positions() const { return positions_; }
    // A slot's image to read (the cached scene's when the slot names it).
    const Image<float>& scalar(Slot s) const { return int(s) == sceneDepthSlot_ ? named_->depth : scalars_[int(s)]; }
    const Image<glm::vec4>& color(Slot s) const { return int(s) == sceneColorSlot_ ? named_->color : colors_[int(s)]; }
    // A slot's image to write.
    Image<float>& scalarOut(Slot s) { return scalars_[int(s)]; }
    Image<glm::vec3>& vec3(Slot s) { return vec3s_[int(s)]; }
    Image<glm::vec4>& colorOut(Slot s) { return colors_[int(s)]; }
    // A colour slot to paint over in place: when it names the cached scene,
    // a copy of the scene (the cache itself is never painted over).
    Image<glm::vec4>& colorToPaint(Slot s);
    Image<float>& scalarToPaint(Slot s);
    // The scene cast (the scene stage): kept while camera and studio stay the
    // same, its slots naming the cached layer itself (no per-frame copy).
    void castScene(Slot color, Slot depth);
    // The geometry stage: `draw` paints the frame's geometry over a copy of
    // the scene cast, kept (and not drawn again) while the camera, the studio
    // and the geometry object stay the same, the slots then naming it; when
    // the slots do not name the cast (a stage run alone on other images),
    // `draw` paints them in place.
    void paintSceneGeometry(Slot color, Slot depth, const std::function<void(Image<glm::vec4>&, Image<float>&)>& draw);
    // The scene as one layer, for the shading: the cached cast when the slots
    // name it (always, in the pipeline), else a copy into *copy.
    const SceneLayer& sceneLayer(Slot color, Slot depth, SceneLayer* copy) const;
    // The geometry stages' rasteriser images, kept across frames.
    MeshRaster& geometryRaster() { return geometryRaster_; }
    // The shadow-map stage: the geometry's depth seen from the key light (the
    // current camera), painted by `draw` into a +inf-filled image and kept (not
    // drawn again) while the light's camera and the geometry object stay the
    // same: the light's camera is snapped (shadowLight), so a still scene
    // draws its casters once.
    const Image<float>& casterDepth(const std::function<void(Image<float>&)>& draw);

private:
    std::span<const glm::vec3> positions_;
    FrameSettings s_;
    Image<float> scalars_[kSlotCount];
    Image<glm::vec3> vec3s_[kSlotCount];
    Image<glm::vec4> colors_[kSlotCount];
    // The last scene cast, kept while camera and studio stay the same.
    bool sceneValid_ = false;
    Camera sceneCamera_;
    shared::Studio sceneStudio_;
    shared::EnvironmentMap sceneEnv_;  // and the environment map
    std::shared_ptr<const EnvironmentImage> sceneEnvImage_;  // kept alive while cached (its address is the key)
    std::shared_ptr<const BackdropImage> sceneBackdrop_;  // the backdrop the cast is of, or null (the studio)
    SceneLayer scene_;
    // The cast with the geometry drawn over it, for the geometry it was drawn with.
    SceneLayer withGeometry_;
    std::shared_ptr<const SceneGeometry> drawnGeometry_;
    bool withGeometryValid_ = false;
    const SceneLayer* named_ = &scene_;
    // The geometry's depth from the key light, for the geometry and light camera it was drawn with.
    Image<float> casterDepth_;
    std::shared_ptr<const SceneGeometry> casterGeometry_;
    Camera casterCamera_;
    bool casterValid_ = false;
    MeshRaster geometryRaster_;  // the layer the scene slots name: the cast, or the cast with geometry
    int sceneColorSlot_ = -1, sceneDepthSlot_ = -1;
    std::string stage_;
    std::chrono::steady_clock::time_point t0_;
    std::vector<StageTime> times_;
};

}  // namespace meniscus::cpu
