// The viewer's panels with Dear ImGui (view_ui.h). The option widgets are
// made from the library's option table (each row's PanelWidget: header,
// range, when shown) and edit UiModel::look, which the viewer checks as the
// command line does after a change (scene_save.h).
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

#include "meniscus/options.h"
#include "meniscus/params.h"

namespace meniscus::app {

#if MENISCUS_HAVE_IMGUI
bool viewerHasPanels() { return true; }
#else
bool viewerHasPanels() { return false; }
#endif

std::string timelineLabel(std::size_t index, std::size_t count, long number) {
    const std::string where = std::to_string(index + 1) + " of " + std::to_string(count);
    return number >= 0 ? std::to_string(number) + " (" + where + ")" : where;
}

#if MENISCUS_HAVE_IMGUI
namespace {

constexpr int kSettleFrames = 3;       // a new window's widgets have their places after this many frames


// The headers of the option widgets, in order (each option's header is its
// table row's PanelWidget::panel).
const char* const kPanels[] = {"Surface",        "Material",  "Anisotropy", "Scene and light",
                               "Noise and foam", "Whitening", "Spray",      "Silhouette"};

// What an option left at "not given" amounts to, shown on its widget: the
// filter's own iterations; the first preset's material values; the light's
// default direction; the radius in use.
Material firstPreset(const meniscus::RenderOptions& o) {
    Material preset;
    materialPreset(o.material.substr(0, o.material.find(',')), &preset);
    return preset;
}
int unsetInt(const std::string& name, const meniscus::RenderOptions& o) {
    if (name != "iterations") return 0;
    FilterParams filter;
    filterFromName(o.filter, &filter);
    return filterIterations(filter);
}
float unsetFloat(const std::string& name, const meniscus::RenderOptions& o, const UiModel& m) {
    const Material p = firstPreset(o);
    if (name == "radius") return m.radiusM;
    if (name == "ior") return p.ior;
    if (name == "refraction") return p.refraction;
    if (name == "specular") return p.specular;
    if (name == "shininess") return p.shininess;
    if (name == "opacity") return p.opacity;
    return 0.0f;
}
glm::vec3 unsetVec3(const std::string& name, const meniscus::RenderOptions& o) {
    if (name == "fluid-color") return firstPreset(o).fluidColor;
    if (name == "absorption") return firstPreset(o).absorptionPerM;
    if (name == "light") return ShadingParams{}.lightDirWorld;
    return glm::vec3(0.0f);
}

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

    if (visible) {
        ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Once);
        ImGui::SetNextWindowSize(ImVec2(float(kViewerPanelWidth), ImGui::GetIO().DisplaySize.y), ImGuiCond_Once);
        ImGui::Begin("meniscus", nullptr, ImGuiWindowFlags_NoCollapse);
        panelWidthPx_ = int(std::lround(ImGui::GetWindowWidth() * ImGui::GetIO().DisplayFramebufferScale.x));
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
        if (!m.geometryNames.empty() && header("Scene geometry", true)) {
            for (std::size_t k = 0; k < m.geometryNames.size() && k < m.geometryShown.size(); ++k) {
                bool shown = m.geometryShown[k] != 0;
                const std::string label = m.geometryNames[k] + "##geometry" + std::to_string(k);
                if (check(label.c_str(), shown)) {
                    m.geometryShown[k] = shown ? 1 : 0;
                    req.geometryChanged = true;
                }
            }
        }
        // Every option with a widget in the table (include/meniscus/options.h),
        // under its header, in the table's order.
        const auto shownNow = [&](const PanelWidget& w) {
            if (w.shownWith.empty()) return true;
            const std::size_t eq = w.shownWith.find('=');
            const RenderOptionSpec* other = findRenderOption(w.shownWith.substr(0, eq));
            return other && optionText(other->field(o)) == w.shownWith.substr(eq + 1);
        };
        const auto widget = [&](const std::string& name, const std::string& unit, const PanelWidget& w,
                                const OptionLimits& limits, const OptionRef& ref) {
            if (!shownNow(w)) return;
            const std::string labelText = widgetLabel(name, unit);
            const char* label = labelText.c_str();
            std::visit(
                [&](auto* p) {
                    using T = std::remove_pointer_t<decltype(p)>;
                    if constexpr (std::is_same_v<T, bool>) {
                        check(label, *p);
                    } else if constexpr (std::is_same_v<T, std::string>) {
                        if (limits.choices == std::vector<std::string>{"on", "off"}) {
                            bool on = *p == "on";
                            if (check(label, on)) *p = on ? "on" : "off";
                        } else {
                            combo(label, *p, w.choices.empty() ? limits.choices : w.choices);
                        }
                    } else if constexpr (std::is_same_v<T, int>) {
                        int shown = *p == limits.unset ? unsetInt(name, o) : *p;
                        if (sliderInt(label, shown, int(w.lo), int(w.hi))) *p = shown;
                    } else if constexpr (std::is_same_v<T, float>) {
                        if (!w.choices.empty()) {
                            std::string text = optionText(p);
                            if (combo(label, text, w.choices)) *p = std::stof(text);
                            return;
                        }
                        const float inUse = std::max(m.radiusM, 1e-6f);  // `relative`: the radius in use
                        float shown = std::isnan(*p) || (w.relative && *p == 0.0f) ? unsetFloat(name, o, m) : *p;
                        const float scale = w.relative ? inUse : 1.0f;
                        if (slider(label, shown, w.lo * scale, w.hi * scale, w.relative ? "%.4g" : "%.3g", w.log))
                            *p = shown;
                    } else if constexpr (std::is_same_v<T, std::optional<glm::vec3>>) {
                        float v[3];
                        const glm::vec3 shown = *p ? **p : unsetVec3(name, o);
                        v[0] = shown.x, v[1] = shown.y, v[2] = shown.z;
                        const bool edited =
                            w.colour ? ImGui::ColorEdit3(label, v, ImGuiColorEditFlags_Float)
                                     : ImGui::DragFloat3(label, v, 0.01f * std::min(w.hi - w.lo, 5.0f), w.lo, w.hi,
                                                         "%.3g");
                        if (changed(edited, label)) *p = glm::vec3(v[0], v[1], v[2]);
                    }
                },
                ref);
        };
        for (const char* panel : kPanels) {
            const std::string title = panel;
            if (!header(panel, title == "Surface" || title == "Material")) continue;
            for (const RenderOptionSpec& spec : renderOptionTable())
                if (spec.widget.panel == title) widget(spec.name, spec.unit, spec.widget, spec.limits, spec.field(o));
            for (const MesherOptionSpec& spec : mesherOptionTable())
                if (spec.widget.panel == title)
                    widget(spec.name, spec.unit, spec.widget, spec.limits, spec.field(o.mesher));
            if (title == "Material" && button("preset values")) {
                o.fluidColor.reset();
                o.absorption.reset();
                o.ior = o.refraction = o.specular = o.shininess = o.opacity = NAN;
                req.lookChanged = true;
            }
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
