// The CPU reference backend (cpu_backend.h): the frame, the images per slot,
// the scene's cache, timing and read-back. The stages are the drivers in
// their own files.
#include "cpu/cpu_backend.h"

#include <limits>

#include "core/backdrop_layer.h"

namespace meniscus::cpu {

Status CpuBackend::beginFrame(std::span<const glm::vec3> positions, const FrameSettings& settings) {
    positions_ = positions;
    s_ = settings;
    times_.clear();
    return okStatus();
}

void CpuBackend::setFluid(std::span<const glm::vec3> positions, const FluidSettings& fluid) {
    positions_ = positions;
    s_.useFluid(fluid);
}

void CpuBackend::beginStage(const char* name) {
    stage_ = name;
    t0_ = std::chrono::steady_clock::now();
}

void CpuBackend::endStage() {
    times_.push_back({stage_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count()});
}

// Hand the frame's images over instead of copying them (tens of MB a frame
// at 1280x720); the cached scene layer is copied, it is kept.
Image<float> CpuBackend::readScalar(Slot slot) {
    return int(slot) == sceneDepthSlot_ ? named_->depth : std::move(scalars_[int(slot)]);
}

Image<glm::vec4> CpuBackend::readColor(Slot slot) {
    return int(slot) == sceneColorSlot_ ? named_->color : std::move(colors_[int(slot)]);
}

void CpuBackend::writeColor(Slot slot, Image<glm::vec4> image) {
    if (int(slot) == sceneColorSlot_) sceneColorSlot_ = -1;  // the slot no longer names the cached cast
    colors_[int(slot)] = std::move(image);
}

Status CpuBackend::present(Slot, const PresentTarget&) {
    return makeError("", "the CPU backend cannot draw into a window (the viewer needs the GL backend)");
}

Image<glm::vec4>& CpuBackend::colorToPaint(Slot s) {
    if (int(s) == sceneColorSlot_) {
        colors_[int(s)] = named_->color;
        sceneColorSlot_ = -1;
    }
    return colors_[int(s)];
}

Image<float>& CpuBackend::scalarToPaint(Slot s) {
    if (int(s) == sceneDepthSlot_) {
        scalars_[int(s)] = named_->depth;
        sceneDepthSlot_ = -1;
    }
    return scalars_[int(s)];
}

void CpuBackend::castScene(Slot color, Slot depth) {
    const shared::EnvironmentMap& env = s_.environment;
    const bool sameEnv = sceneEnv_.texels == env.texels && sceneEnv_.width == env.width &&
                         sceneEnv_.height == env.height && sceneEnv_.rotation == env.rotation &&
                         sceneEnv_.intensity == env.intensity;
    if (!sceneValid_ || !(sceneCamera_ == s_.camera) || !(sceneStudio_ == s_.studio) || !sameEnv ||
        sceneBackdrop_ != s_.backdrop) {
        // A backdrop takes the studio's place (docs/compositing.md).
        if (s_.backdrop) backdropLayer(s_.camera, *s_.backdrop, scene_.color, scene_.depth);
        else scene_ = cpu::castScene(s_.camera, s_.studio, env);
        sceneBackdrop_ = s_.backdrop;
        sceneEnv_ = env;
        sceneEnvImage_ = s_.environmentImage;
        sceneCamera_ = s_.camera;
        sceneStudio_ = s_.studio;
        sceneValid_ = true;
        withGeometryValid_ = false;
    }
    named_ = &scene_;
    sceneColorSlot_ = int(color);
    sceneDepthSlot_ = int(depth);
}

void CpuBackend::paintSceneGeometry(Slot color, Slot depth,
                                    const std::function<void(Image<glm::vec4>&, Image<float>&)>& draw) {
    if (int(color) != sceneColorSlot_ || int(depth) != sceneDepthSlot_) {
        draw(colorToPaint(color), scalarToPaint(depth));
        return;
    }
    if (!withGeometryValid_ || drawnGeometry_ != s_.geometry) {
        withGeometry_ = scene_;
        draw(withGeometry_.color, withGeometry_.depth);
        drawnGeometry_ = s_.geometry;
        withGeometryValid_ = true;
    }
    named_ = &withGeometry_;
}

const Image<float>& CpuBackend::casterDepth(const std::function<void(Image<float>&)>& draw) {
    if (!casterValid_ || casterGeometry_ != s_.geometry || !(casterCamera_ == s_.camera)) {
        casterDepth_ = Image<float>(s_.camera.width, s_.camera.height, std::numeric_limits<float>::infinity());
        draw(casterDepth_);
        casterGeometry_ = s_.geometry;
        casterCamera_ = s_.camera;
        casterValid_ = true;
    }
    return casterDepth_;
}

const SceneLayer& CpuBackend::sceneLayer(Slot color, Slot depth, SceneLayer* copy) const {
    if (int(color) == sceneColorSlot_ && int(depth) == sceneDepthSlot_) return *named_;
    *copy = {this->color(color), scalar(depth)};
    return *copy;
}

}  // namespace meniscus::cpu

namespace meniscus {

std::unique_ptr<Backend> makeCpuBackend() { return std::make_unique<cpu::CpuBackend>(); }

}  // namespace meniscus
