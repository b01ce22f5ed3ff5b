// The viewer's panels, drawn with Dear ImGui over the rendered picture: every
// stage's settings (as `render`'s options, so what is tuned here is what
// `render` draws), the camera, the sequence's timeline, per-stage times, scene
// files and a help overlay. Built only with GLFW and libimgui-dev
// (MENISCUS_HAVE_IMGUI); the viewer works without it, panel-less.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common.h"
#include "meniscus/camera.h"
#include "meniscus/renderer.h"
#include "meniscus/window.h"

namespace meniscus::app {

// The panels' width, screen units: the viewer's window is this much wider
// than --width, and the picture is drawn beside the panels, not under them.
inline constexpr int kViewerPanelWidth = 330;
// Whether this build has the panels (Dear ImGui).
bool viewerHasPanels();

// What the panels show and edit; the viewer owns it and acts on UiRequests.
struct UiModel {
    RenderJob look;      // every look option, edited in place by the panels
    float radiusM = 0.0f;    // the radius in use (look.radius is 0 while estimated)
    Camera camera;           // the view; the panels edit its fov
    // The sequence: frame index of count, playback.
    std::size_t frame = 0, frameCount = 1;
    // The shown frame's own number, as its file name says (ParticleData_Fluid_21
    // -> 21; -1 when the name has none): the timeline counts as the files do.
    long frameNumber = -1;
    bool playing = false, loop = true;
    float speed = 1.0f;      // times look.fps frames per second
    // Statistics of the last drawn frame.
    std::string backend;
    double drawMs = 0.0;                 // wall clock of the last draw, ms
    double framesPerSecond = 0.0;        // shown per second, smoothed
    std::vector<StageTime> stages;       // per-stage times (GL: GPU timer queries)
    std::string scenePath = "scene.json";  // the scene file's name for Save and Load
    // The scene geometry's objects (RenderSettings::geometry): name, and
    // whether it is drawn (a checkbox each; 1 = shown).
    std::vector<std::string> geometryNames;
    std::vector<char> geometryShown;
    std::string message;                 // the last thing done or gone wrong, shown at the bottom
    bool showHelp = false;
};

// What the user asked for in one frame of the panels.
struct UiRequests {
    bool lookChanged = false;    // model.look changed
    bool fovChanged = false;     // model.camera.fovYDegrees changed
    bool copyCamera = false, resetCamera = false;
    bool save = false, load = false;
    bool geometryChanged = false;  // model.geometryShown changed
    long seek = -1;              // show this frame (timeline slider, step buttons)
};

class ViewerUi {
public:
    // The panels on `window` (its context current): ImGui's GLFW and OpenGL 3
    // backends, their callbacks chained to the window's own.
    static std::unique_ptr<ViewerUi> create(Window& window);
    ~ViewerUi();
    ViewerUi(const ViewerUi&) = delete;
    ViewerUi& operator=(const ViewerUi&) = delete;

    // The panels have the mouse (hovered or in use) or the keyboard (a text
    // field): the viewer then leaves drags, wheel and keys to them.
    bool wantsMouse() const;
    bool wantsKeyboard() const;

    // A scripted pointer for this frame (tests, --input-script "click:LABEL@F"):
    // over widget `label` at fraction `f` of its width, the button down or up.
    // False when no widget by that label was drawn in the last frame.
    bool scriptPointer(const std::string& label, float f, bool down);

    // Builds this frame's panels over `model` (shown only when `visible`) and
    // draws them into the current framebuffer.
    UiRequests frame(UiModel& model, bool visible);

    // The panels' width in framebuffer pixels as last drawn (the user may
    // widen them); where the picture starts.
    int panelWidthPx() const { return panelWidthPx_; }

private:
    ViewerUi() = default;
    struct Widget {
        glm::vec4 box{0.0f};  // min x, min y, max x, max y (screen units)
        int frames = 0;       // frames in a row it has been drawn
    };
    std::map<std::string, Widget> widgets_;  // by label (a combo's items as "combo/item"), of the last frame
    bool scripted_ = false, scriptedDown_ = false;
    int panelWidthPx_ = kViewerPanelWidth;
    glm::vec2 scriptedAt_{0.0f};
};

// The timeline's text for frame `index` of `count` whose file carries the
// number `number` (-1: none): "21 (3 of 60)", or "3 of 60".
std::string timelineLabel(std::size_t index, std::size_t count, long number);

}  // namespace meniscus::app
