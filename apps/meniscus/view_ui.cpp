// The viewer's panels with Dear ImGui (view_ui.h). Every widget edits a
// `render` option in UiModel::look; the viewer reparses the options after a
// change (scene_save.h), so a slider can only reach values the command line
// can name.
#include "view_ui.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#if MENISCUS_HAVE_IMGUI
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#endif

#include "meniscus/params.h"

namespace meniscus::app {

std::string timelineLabel(std::size_t index, std::size_t count, long number) {
    const std::string where = std::to_string(index + 1) + " of " + std::to_string(count);
    return number >= 0 ? std::to_string(number) + " (" + where + ")" : where;
}

#if MENISCUS_HAVE_IMGUI
namespace {

constexpr float kPanelWidth = 330.0f;  // screen units; the picture shows beside and under it
constexpr int kSettleFrames = 3;       // a new window's widgets have their places after this many frames

std::vector<std::string> splitList(const std::string& list) {  // "a, b, c" -> {a, b, c}
    std::vector<std::string> out;
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) {
        item.erase(0, item.find_first_not_of(' '));
        item.erase(item.find_last_not_of(' ') + 1);
        if (!item.empty()) out.push_back(item);
    }
    return out;
}

// A vector option's three floats, shown as the default's when unset.
void get3(const std::optional<glm::vec3>& v, float* out) {
    if (v) out[0] = v->x, out[1] = v->y, out[2] = v->z;
}
glm::vec3 vec3Of(const float* v) { return {v[0], v[1], v[2]}; }

// The help overlay's lines: key, what it does.
constexpr const char* kHelp[][2] = {
    {"drag (left button)", "orbit the camera around its target"},
    {"wheel", "zoom"},
    {"left / right", "previous / next frame of a sequence"},
    {"space", "play / pause a sequence"},
    {"Tab", "hide / show the panels"},
    {"C", "copy the camera: print --eye --target --fov (and to the clipboard)"},
    {"H or F1", "this help"},
    {"drop a file or folder", "show it (a .json scene file: load its settings)"},
    {"Esc or Q", "quit"},
};

}  // namespace

std::unique_ptr<ViewerUi> ViewerUi::create(Window& window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini in the user's folder
    ImGui::StyleColorsDark();
    ImGui::GetStyle().Alpha = 0.92f;
    ImGui_ImplGlfw_InitForOpenGL(window.glfwHandle(), true);  // chained to the window's own callbacks
    ImGui_ImplOpenGL3_Init("#version 330 core");
    return std::unique_ptr<ViewerUi>(new ViewerUi);
}

ViewerUi::~ViewerUi() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

bool ViewerUi::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }
bool ViewerUi::wantsKeyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

bool ViewerUi::scriptPointer(const std::string& label, float f, bool down) {
    // Shown for a few frames in a row: a new window (a combo's list) has its places by then.
    const auto it = widgets_.find(label);
    if (it == widgets_.end() || it->second.frames < kSettleFrames) return false;
    const glm::vec4 r = it->second.box;
    scripted_ = true;
    scriptedDown_ = down;
    scriptedAt_ = {r.x + f * (r.z - r.x), 0.5f * (r.y + r.w)};
    return true;
}

UiRequests ViewerUi::frame(UiModel& m, bool visible) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    if (scripted_) {  // after the backend has read the real pointer
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = ImVec2(scriptedAt_.x, scriptedAt_.y);
        io.MouseDown[0] = scriptedDown_;
        scripted_ = false;
    }
    ImGui::NewFrame();
    UiRequests req;
    RenderJob& o = m.look;
    // Every widget is recorded by its label, for scripted input.
    std::map<std::string, Widget> drawn;  // this frame's widgets
    const auto note = [&](const std::string& label) {
        // The item's box, less the label to the right of a slider or field (the item width).
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        Widget& w = drawn[label];
        w.box = {a.x, a.y, std::min(b.x, a.x + ImGui::CalcItemWidth()), b.y};
        const auto before = widgets_.find(label);
        w.frames = before == widgets_.end() ? 1 : before->second.frames + 1;
    };
    const auto changed = [&](bool edited, const char* label) {
        note(label);
        req.lookChanged |= edited;
        return edited;
    };
    const auto combo = [&](const char* label, std::string& value, const std::vector<std::string>& items) {
        bool edited = false;
        if (ImGui::BeginCombo(label, value.c_str())) {
            for (const std::string& item : items) {
                if (ImGui::Selectable(item.c_str(), item == value) && item != value) {
                    value = item;
                    edited = true;
                }
                note(std::string(label) + "/" + item);  // a script picks it as "click:surface/raycast"
            }
            ImGui::EndCombo();
        }
        return changed(edited, label);
    };
    const auto slider = [&](const char* label, float& v, float lo, float hi, const char* fmt = "%.3g",
                            bool log = false) {
        return changed(ImGui::SliderFloat(label, &v, lo, hi, fmt, log ? ImGuiSliderFlags_Logarithmic : 0), label);
    };
    const auto sliderInt = [&](const char* label, int& v, int lo, int hi) {
        return changed(ImGui::SliderInt(label, &v, lo, hi), label);
    };
    const auto header = [&](const char* label, bool open = false) {
        const bool shown = ImGui::CollapsingHeader(label, open ? ImGuiTreeNodeFlags_DefaultOpen : 0);
        note(label);
        return shown;
    };
    const auto button = [&](const char* label) {
        const bool pressed = ImGui::Button(label);
        note(label);
        return pressed;
    };
    const auto check = [&](const char* label, bool& v) { return changed(ImGui::Checkbox(label, &v), label); };
    // A custom material value: the preset's until edited (NaN in the options).
    const auto materialValue = [&](const char* label, float& v, float preset, float lo, float hi, bool log = false) {
        float shown = std::isnan(v) ? preset : v;
        if (slider(label, shown, lo, hi, "%.3g", log)) v = shown;
    };

    if (visible) {
        ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Once);
        ImGui::SetNextWindowSize(ImVec2(kPanelWidth, ImGui::GetIO().DisplaySize.y), ImGuiCond_Once);
        ImGui::Begin("meniscus", nullptr, ImGuiWindowFlags_NoCollapse);
        ImGui::PushItemWidth(-150.0f);

        if (header("Sequence", true)) {
            int frame = int(m.frame);
            if (m.frameCount > 1) {
                // The slider moves through the frames in order; its text is the
                // file's own number (as the files count, often from 1) and the
                // position: "21 (3 of 60)". No '%' in it, so ImGui shows it as it is.
                const std::string text = timelineLabel(m.frame, m.frameCount, m.frameNumber);
                if (ImGui::SliderInt("frame", &frame, 0, int(m.frameCount) - 1, text.c_str())) req.seek = frame;
                note("frame");
                if (button("<")) req.seek = long((m.frame + m.frameCount - 1) % m.frameCount);
                ImGui::SameLine();
                if (button(m.playing ? "pause" : "play")) m.playing = !m.playing;
                ImGui::SameLine();
                if (button(">")) req.seek = long((m.frame + 1) % m.frameCount);
                ImGui::SameLine();
                ImGui::Checkbox("loop", &m.loop);
                note("loop");
                ImGui::SliderFloat("speed", &m.speed, 0.1f, 4.0f, "%.2gx", ImGuiSliderFlags_Logarithmic);
                note("speed");
                ImGui::Text("%.3g frames per second at 1x (--fps)", o.fps);
            } else {
                ImGui::TextUnformatted("one frame");
            }
        }
        if (header("Camera", true)) {
            req.fovChanged = ImGui::SliderFloat("fov (degrees)", &m.camera.fovYDegrees, 5.0f, 120.0f, "%.1f");
            note("fov (degrees)");
            if (button("copy camera")) req.copyCamera = true;
            ImGui::SameLine();
            if (button("reset camera")) req.resetCamera = true;
        }
        if (header("Scene file", true)) {
            char path[1024];
            std::snprintf(path, sizeof path, "%s", m.scenePath.c_str());
            if (ImGui::InputText("file", path, sizeof path)) m.scenePath = path;
            note("file");
            if (button("save")) req.save = true;
            ImGui::SameLine();
            if (button("load")) req.load = true;
        }
        if (header("Surface", true)) {
            combo("surface", o.surface, {"screen", "raycast"});
            combo("view", o.view, splitList(viewNames()));
            combo("filter", o.filter, splitList(filterNames()));
            FilterParams filter;
            filterFromName(o.filter, &filter);
            int iterations = o.iterations >= 0 ? o.iterations : filterIterations(filter);
            if (sliderInt("iterations", iterations, 0, 100)) o.iterations = iterations;
            check("separable", o.separable);
            float radius = o.radius > 0.0f ? o.radius : m.radiusM;
            const float r0 = std::max(m.radiusM, 1e-6f);
            if (slider("radius (m)", radius, 0.25f * r0, 4.0f * r0, "%.4g", true)) o.radius = radius;
            slider("fill holes (radii)", o.fillHoles, 0.0f, 16.0f);
            slider("min thickness (radii)", o.minThickness, 0.0f, 4.0f);
            if (o.surface == "raycast") {
                slider("iso level", o.mesher.iso, 0.05f, 0.95f);
                slider("raycast step (radii)", o.raycastParams.stepRadii, 0.05f, 2.0f);
                slider("raycast cover (radii)", o.raycastParams.coverRadii, 1.0f, 4.0f);
            }
            std::string scale = o.fluidScale == 1.0f ? "1" : o.fluidScale == 0.5f ? "0.5" : "0.25";
            if (combo("fluid scale", scale, {"1", "0.5", "0.25"})) o.fluidScale = std::stof(scale);
        }
        if (header("Material", true)) {
            combo("preset", o.material, splitList(materialPresetNames()));
            Material preset;
            materialPreset(o.material.substr(0, o.material.find(',')), &preset);
            float color[3] = {preset.fluidColor.r, preset.fluidColor.g, preset.fluidColor.b};
            get3(o.fluidColor, color);
            if (changed(ImGui::ColorEdit3("fluid colour", color, ImGuiColorEditFlags_Float), "fluid colour"))
                o.fluidColor = vec3Of(color);
            float absorb[3] = {preset.absorptionPerM.r, preset.absorptionPerM.g, preset.absorptionPerM.b};
            get3(o.absorption, absorb);
            if (changed(ImGui::DragFloat3("absorption (1/m)", absorb, 0.05f, 0.0f, 1000.0f, "%.3g"),
                        "absorption (1/m)"))
                o.absorption = vec3Of(absorb);
            materialValue("IOR", o.ior, preset.ior, 1.0f, 2.5f);
            materialValue("refraction", o.refraction, preset.refraction, 0.0f, 4.0f);
            materialValue("specular", o.specular, preset.specular, 0.0f, 4.0f);
            materialValue("shininess", o.shininess, preset.shininess, 1.0f, 4000.0f, true);
            materialValue("opacity", o.opacity, preset.opacity, 0.0f, 1.0f);
            if (button("preset values")) {
                o.fluidColor.reset();
                o.absorption.reset();
                o.ior = o.refraction = o.specular = o.shininess = o.opacity = NAN;
                req.lookChanged = true;
            }
        }
        if (header("Anisotropy")) {
            bool on = o.anisotropy == "on";
            if (check("anisotropic kernels", on)) o.anisotropy = on ? "on" : "off";
            AnisotropyParams& a = o.anisotropyParams;
            slider("neighbourhood (radii)", a.neighbourRadii, 1.0f, 8.0f);
            slider("max axis ratio", a.kr, 1.0f, 16.0f);
            slider("isolated size (radii)", a.kn, 0.05f, 1.0f);
            sliderInt("min neighbours", a.minNeighbours, 1, 50);
            check("keep surface", a.keepSurface);
            slider("centre smoothing", a.smoothing, 0.0f, 1.0f);
        }
        if (header("Scene and light")) {
            combo("background", o.background, {"auto", "studio", "floor", "none"});
            const glm::vec3 l = ShadingParams{}.lightDirWorld;
            float light[3] = {l.x, l.y, l.z};
            get3(o.light, light);
            if (changed(ImGui::DragFloat3("light (toward)", light, 0.02f, -1.0f, 1.0f, "%.2f"), "light (toward)"))
                o.light = vec3Of(light);
        }
        if (header("Noise and foam")) {
            check("noise", o.noise);
            NoiseParams& q = o.noiseParams;
            slider("bump (sprite radii)", q.bump, 0.0f, 1.0f);
            slider("frequency (per radius)", q.frequency, 0.05f, 4.0f, "%.3g", true);
            sliderInt("octaves", q.octaves, 1, 6);
            slider("foam", q.foamGain, 0.0f, 8.0f);
            slider("turbulence tau (m/s)", q.turbulence.tauMps, 0.01f, 10.0f, "%.3g", true);
        }
        if (header("Whitening")) {
            check("whiten", o.whiten);
            slider("threshold (m/s)", o.whitening.thresholdMps, 0.0f, 10.0f);
            slider("ramp (m/s)", o.whitening.rampMps, 0.01f, 10.0f);
            slider("strength", o.whitening.strength, 0.0f, 1.0f);
        }
        if (header("Spray")) {
            check("spray", o.spray);
            slider("spray density (of rest)", o.sprayParams.sprayDensity, 0.0f, 1.0f);
            slider("rest density (kg/m^3)", o.sprayParams.restDensityKgM3, 0.0f, 3000.0f);
            slider("drop size (radii)", o.sprayParams.sizeRadii, 0.05f, 2.0f);
            slider("streak (s)", o.sprayParams.streakSeconds, 0.0f, 0.2f);
        }
        if (header("Silhouette")) {
            check("silhouette", o.silhouette);
            slider("window (radii)", o.silhouetteParams.radiusRadii, 0.5f, 8.0f);
            slider("fade from", o.silhouetteParams.fadeFrom, 0.0f, 1.0f);
        }
        if (header("Timings", true)) {
            ImGui::Text("%s", m.backend.c_str());
            ImGui::Text("%.1f frames/s shown, last draw %.1f ms", m.framesPerSecond, m.drawMs);
            if (ImGui::BeginTable("stages", 2)) {
                for (const StageTime& t : m.stages) {
                    ImGui::TableNextRow();
                    ImGui::TableNextColumn();
                    ImGui::TextUnformatted(t.stage.c_str());
                    ImGui::TableNextColumn();
                    ImGui::Text("%7.2f ms", t.ms);
                }
                ImGui::EndTable();
            }
        }
        if (button("help (H)")) m.showHelp = !m.showHelp;
        if (!m.message.empty()) ImGui::TextWrapped("%s", m.message.c_str());
        ImGui::PopItemWidth();
        ImGui::End();
    }
    if (m.showHelp) {
        const ImVec2 size = ImGui::GetIO().DisplaySize;
        ImGui::SetNextWindowPos(ImVec2(0.5f * size.x, 0.5f * size.y), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
        ImGui::Begin("keys", &m.showHelp, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
        if (ImGui::BeginTable("keys", 2)) {
            for (const auto& line : kHelp) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(line[0]);
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(line[1]);
            }
            ImGui::EndTable();
        }
        ImGui::End();
    }
    widgets_ = std::move(drawn);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    return req;
}

#else  // no Dear ImGui: a viewer without panels

std::unique_ptr<ViewerUi> ViewerUi::create(Window&) { return nullptr; }
ViewerUi::~ViewerUi() = default;
bool ViewerUi::wantsMouse() const { return false; }
bool ViewerUi::wantsKeyboard() const { return false; }
bool ViewerUi::scriptPointer(const std::string&, float, bool) { return false; }
UiRequests ViewerUi::frame(UiModel&, bool) { return {}; }

#endif

}  // namespace meniscus::app
