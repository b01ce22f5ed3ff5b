// `meniscus view` (see view.h). A frame is rendered only when something it
// depends on changes (camera, window size, the frame of a sequence, a new
// frame of a live simulation, whose worker wakes the loop) and the
// loop sleeps in waitEvents between, so an idle viewer costs nothing; the last
// frame is drawn again when the window loses its contents.
#include "view.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <unistd.h>

#if MENISCUS_HAVE_GLFW
#include "meniscus/window.h"
#include "view_ui.h"
#endif
#include "meniscus/boundary.h"
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/renderer.h"
#include "meniscus/sim.h"
#include "frame_prefetch.h"
#include "live_simulation.h"
#include "scene_file.h"
#include "scene_save.h"

namespace meniscus::app {

#if !MENISCUS_HAVE_GLFW

int runView(const ViewOptions&, const ParticleSet*) {
    return fail("this build has no viewer (it was configured without GLFW or without the GL backend); "
                "`meniscus render` writes images without one");
}

#else

namespace {

// Columns [left, left + width) of `image`: the picture beside the panels.
Image<glm::u8vec4> cropColumns(const Image<glm::u8vec4>& image, int left, int width) {
    if (left == 0 && width == image.width) return image;
    Image<glm::u8vec4> out(width, image.height);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < width; ++x) out.at(x, y) = image.at(left + x, y);
    return out;
}

constexpr float kDegreesPerDragUnit = 0.3f;  // orbit per screen unit the cursor moves with the button held
constexpr float kZoomPerWheelStep = 0.9f;    // camera distance factor per wheel step away from the user
constexpr double kLiveSpeed = 1.0;  // --simulate: at most real time (simulated s per wall-clock s), so a fast scene plays
constexpr int kUiSettleFrames = 3;  // the panels react to hover and lay out over a few frames after an event
constexpr std::size_t kPrefetchAhead = 4;  // frames read ahead of the one shown
constexpr int kScriptWidgetFrames = 60;  // a scripted click waits this many frames for its widget to be drawn

// One event of an input script: window input, or the pointer over a panel widget.
struct ScriptEvent {
    WindowInput in;
    std::string widget;  // click: the widget's label (empty for the other events)
    float at = 0.5f;     // where on the widget, as a fraction of its width
    bool down = false;   // the button
};

// The events of an input script ("drag:DX,DY;scroll:N;key:K;drop:PATH;click:LABEL@F"); a
// click is three events: the pointer over the widget, the button down, up.
Result<std::vector<ScriptEvent>> parseInputScript(const std::string& script) {
    static const std::pair<const char*, Key> kKeys[] = {
        {"left", Key::Left}, {"right", Key::Right}, {"q", Key::Q}, {"escape", Key::Escape}, {"space", Key::Space},
        {"tab", Key::Tab},   {"h", Key::H},         {"c", Key::C}};
    std::vector<ScriptEvent> events;
    std::stringstream all(script);
    std::string item;
    while (std::getline(all, item, ';')) {
        if (item.empty()) continue;
        ScriptEvent e;
        double a = 0.0, b = 0.0;
        char end = 0;
        bool ok = true;
        if (std::sscanf(item.c_str(), "drag:%lf,%lf%c", &a, &b, &end) == 2 && std::isfinite(a) && std::isfinite(b)) {
            e.in.drag = glm::dvec2(a, b);
        } else if (std::sscanf(item.c_str(), "scroll:%lf%c", &a, &end) == 1 && std::isfinite(a)) {
            e.in.scroll = a;
        } else if (item.rfind("drop:", 0) == 0 && item.size() > 5) {
            e.in.dropped.push_back(item.substr(5));
        } else if (item.rfind("click:", 0) == 0) {
            const std::size_t at = item.rfind('@');
            e.widget = item.substr(6, at == std::string::npos ? std::string::npos : at - 6);
            if (at != std::string::npos)
                ok = std::sscanf(item.c_str() + at + 1, "%f%c", &e.at, &end) == 1 && e.at >= 0.0f && e.at <= 1.0f;
            ok = ok && !e.widget.empty();
            if (ok) {
                events.push_back(e);  // over it
                e.down = true;
                events.push_back(e);  // pressed
                e.down = false;       // and released below
            }
        } else if (item.rfind("key:", 0) == 0) {
            ok = false;
            for (const auto& [name, key] : kKeys)
                if (item.substr(4) == name) {
                    e.in.keys.push_back(key);
                    ok = true;
                }
        } else {
            ok = false;
        }
        if (!ok)
            return makeError("", "--input-script: '" + item +
                                     "' is not an event (drag:DX,DY, scroll:N, key:left|right|space|tab|h|c|q|escape, "
                                     "drop:PATH, click:LABEL@FRACTION; separated by ;)");
        events.push_back(std::move(e));
    }
    return events;
}

std::string title(const RenderJob& o, std::size_t count, std::size_t index, const Frames* frames) {
    std::string t = "meniscus view: " + (o.input.empty() ? std::string("demo") : o.input);
    if (count > 1 && frames)
        t += " (" + std::to_string(index + 1) + "/" + std::to_string(count) + ": " +
             frames->files[index].filename().string() + ")";
    return t;
}

std::string liveTitle(const ViewOptions& o, const sim::Scene& scene, const LiveSimulation::Frame& f, bool running) {
    char t[64];
    std::snprintf(t, sizeof t, "t = %.3f of %g s, %zu particles", f.time, scene.duration, f.particles->size());
    return "meniscus view: " + o.simulate + " (" + t + (running ? ")" : ", done)");
}

// The frames of o.input (the demo frame when empty) with its fluids and up
// axis: what can fail about an input before a window is worth opening.
Result<Frames> openSequence(const RenderJob& o, const ParticleSet* embedded) {
    auto opened = openFrames(o.input, o.input.empty() ? embedded : nullptr, o.hPerSpacing);
    if (!opened) return opened.error();
    if (auto st = opened->addFluids(o); !st) return st.error();
    auto up = upRotation(o.up);
    if (!up) return up.error();
    opened->up = *up;
    return opened;
}

// `frames` with the camera, radius and studio fixed for them in `settings`,
// framed for a `size` framebuffer, and the first frame that loads.
struct Opened {
    Frames frames;
    std::shared_ptr<const ParticleSet> first;
    std::size_t firstIndex = 0;
};
Result<Opened> frameInput(const RenderJob& o, Frames frames, glm::ivec2 size, RenderSettings& settings) {
    RenderJob sized = o;
    if (size.x > 0 && size.y > 0) {
        sized.width = size.x;
        sized.height = size.y;
    }
    std::size_t firstIndex = 0;
    auto first = fixForSequence(sized, frames, settings, &firstIndex);
    if (!first) return first.error();
    printWarnings(*first);
    return Opened{std::move(frames), std::make_shared<const ParticleSet>(std::move(*first)), firstIndex};
}

// "--eye x,y,z --target x,y,z --fov f" of `camera` in the data's frame (o.up), every digit a float has,
// so `render` with them draws the same picture.
std::string cameraOptions(const Camera& camera, const glm::vec3& upAxis) {
    auto up = upRotation(upAxis);
    const UpRotation back = up ? up->inverse() : UpRotation{};  // renderer -> data
    const glm::vec3 e = back.apply(camera.eye), t = back.apply(camera.target);
    char line[256];
    std::snprintf(line, sizeof line, "--eye %.9g,%.9g,%.9g --target %.9g,%.9g,%.9g --fov %.9g", e.x, e.y, e.z, t.x,
                  t.y, t.z, double(camera.fovYDegrees));
    return line;
}

}  // namespace

int runView(const ViewOptions& o, const ParticleSet* embedded) {
    if (o.render.surface == "mesh")
        return failUsage("--surface mesh: the viewer draws the screen-space or ray-cast surface; `meniscus render "
                    "--surface mesh` (or `meniscus mesh`) extracts meshes");
    auto parsed = settingsFromOptions(o.render);
    if (!parsed) return fail(parsed.error());
    RenderSettings settings = std::move(*parsed);
    if (!o.screenshot.empty() && !isPng(o.screenshot)) return fail(o.screenshot + ": --screenshot must end in .png");
    if (!o.screenshotWindow.empty() && !isPng(o.screenshotWindow))
        return fail(o.screenshotWindow + ": --screenshot-window must end in .png");
    auto script = parseInputScript(o.inputScript);
    if (!script) return fail(script.error());

    // A scene simulated live is checked before any window; an input's errors
    // come before the window too (its frames are framed for the window's own size below).
    std::optional<sim::Scene> scene;
    std::optional<Frames> input;
    std::unique_ptr<sim::Simulator> simulator;
    if (!o.simulate.empty()) {
        if (!o.render.select.empty())
            return failUsage("--select " + o.render.select + ": picks particles of files; --simulate shows a simulation, "
                        "whose particles are all its fluid");
        SimulateJob so = o.live;
        so.scene = o.simulate;
        so.radius = o.render.radius;  // one radius: the simulation's and the picture's
        auto read = sceneFromOptions(so);
        if (!read) return fail(read.error());
        auto made = sim::Simulator::create(*read);
        if (!made) return fail(made.error());
        scene = std::move(*read);
        simulator = std::move(*made);
    } else {
        auto opened = openSequence(o.render, embedded);
        if (!opened) return fail(opened.error());
        input = std::move(*opened);
    }

    // The window first: without a display nothing else is worth doing.
    // Wider than --width by the panels, which the picture is drawn beside.
    auto window = Window::create(o.render.width + (viewerHasPanels() ? kViewerPanelWidth : 0), o.render.height,
                                 scene ? "meniscus view: " + o.simulate : title(o.render, 1, 0, nullptr));
    if (!window)
        return fail(window.error().describe() +
                    "; meniscus view needs a display (`meniscus render` writes images without one)");
    Window& win = **window;

    // The picture's area: the framebuffer (its real size: HiDPI screens
    // differ) less the panels on the left while they are shown. `left` is
    // where it starts; before the panels exist, their width in screen units.
    bool panels = true;
    std::unique_ptr<ViewerUi> ui;
    struct Area {
        int left = 0;
        glm::ivec2 size{0};
    };
    const auto pictureArea = [&]() -> Area {
        const glm::ivec2 fb = win.framebufferSize();
        const int panel = !panels || !viewerHasPanels() ? 0 : ui ? ui->panelWidthPx() : kViewerPanelWidth;
        if (fb.x - panel < 16) return {0, fb};  // too narrow beside them: the whole window, under the panels
        return {panel, {fb.x - panel, fb.y}};
    };

    // The camera is framed for the picture's real size.
    std::shared_ptr<const ParticleSet> current;  // what is on screen
    // `current` as drawn: its DualSPHysics boundary particles taken out for
    // this look (--boundary-particles) and the settings' geometry with their walls.
    struct Boundary {
        std::shared_ptr<const ParticleSet> of;
        std::shared_ptr<const SceneGeometry> base;
        std::string mode, cutAway;
        std::shared_ptr<const ParticleSet> liquid;
        std::shared_ptr<const SceneGeometry> geometry;
    } boundary;
    std::set<std::string> wallsHidden;  // the walls unticked in the panel, by name
    std::unique_ptr<FramePrefetch> prefetch;     // the input's frames, read ahead (after the window: joined first)
    std::size_t index = 0;
    RenderJob look = o.render;  // the look as options, as the panels change it
    float estimatedRadius = 0.0f;   // the radius fixed for the input (look.radius 0: this one)
    Camera homeCamera;              // the camera the input opened with (reset camera)
    // Shows o.input (or the one a drop or a scene file names; `frames` when
    // already opened): an error leaves what is shown.
    const auto open = [&](const RenderJob& next, std::optional<Frames> frames) -> Status {
        auto s = settingsFromOptions(next);
        if (!s) return s.error();
        if (!frames) {
            auto opened = openSequence(next, embedded);
            if (!opened) return opened.error();
            frames = std::move(*opened);
        }
        auto opened = frameInput(next, std::move(*frames), pictureArea().size, *s);
        if (!opened) return opened.error();
        prefetch.reset();
        current = opened->first;
        // The frame just read is the reader's first: not read twice.
        prefetch = std::make_unique<FramePrefetch>(std::move(opened->frames), [&win] { win.wake(); },
                                                   kPrefetchAhead, opened->first, opened->firstIndex);
        index = opened->firstIndex;
        settings = std::move(*s);
        look = next;
        estimatedRadius = settings.radiusM;
        homeCamera = settings.camera;
        win.setTitle(title(look, prefetch->frames().count(), index, &prefetch->frames()));
        return okStatus();
    };
    if (scene) {
        // Framed once on the domain, as `simulate --render` frames its images.
        RenderJob sized = o.render;
        const glm::ivec2 fb = pictureArea().size;
        if (fb.x > 0 && fb.y > 0) {
            sized.width = fb.x;
            sized.height = fb.y;
        }
        if (auto st = fixForScene(sized, *scene, settings); !st)
            return fail(st.error());
        estimatedRadius = settings.radiusM;
        homeCamera = settings.camera;
    } else if (auto st = open(o.render, std::move(input)); !st) {
        return fail(st.error());
    }
    const std::size_t count0 = prefetch ? prefetch->frames().count() : 1;

    auto made = Renderer::createOnCurrentGlContext();  // after the window, so destroyed before it
    if (!made) return fail(made.error());
    Renderer renderer = std::move(*made);
    ui = ViewerUi::create(win);  // null in a build without Dear ImGui
    std::cerr << "meniscus: viewing on " << renderer.backendName() << ": drag to orbit, scroll to zoom, "
              << (count0 > 1 ? "left/right for frames, space to play, " : "")
              << (ui ? "Tab for the panels, H for help, " : "") << "Esc or Q to quit\n";

    // After the window, so stopped (joined) before the window goes.
    std::optional<LiveSimulation> live;
    if (scene) {
        std::cerr << "meniscus: simulating " << o.simulate << " live: " << simulator->size()
                  << " particles, r = " << scene->params.radius << " m, " << sim::solverName(scene->params.solver)
                  << ", " << scene->duration << " s at " << scene->fps << " fps\n";
        live.emplace(std::move(simulator), scene->fps, scene->duration, kLiveSpeed);
        live->start([&win] { win.wake(); });  // each new frame wakes the loop below out of waitEvents
    }
    const bool tty = ::isatty(STDERR_FILENO) == 1;

    UiModel model;
    model.backend = renderer.backendName();
    model.scenePath = o.render.sceneFile.empty() ? "scene.json" : o.render.sceneFile;
    int uiFrames = kUiSettleFrames;

    // A frame of the input on screen (waiting for the reader); an error leaves the one shown.
    const auto show = [&](std::size_t next) {
        FramePrefetch::Loaded f = prefetch->wait(next);
        if (!f.set) {
            std::cerr << "meniscus: error: " << f.error << "\n";
            model.message = f.error;
            return;
        }
        printWarnings(*f.set);
        current = f.set;
        index = next;
        win.setTitle(title(look, prefetch->frames().count(), index, &prefetch->frames()));
    };
    // The panels' look, checked and read back as `render` reads its options.
    const auto applyLook = [&](const RenderJob& next) {
        auto re = reparsed(next);
        auto s = re ? settingsFromOptions(*re) : Result<RenderSettings>(re.error());
        if (!s) {
            model.message = s.error().describe();
            std::cerr << "meniscus: error: " << model.message << "\n";
            return;
        }
        s->camera = settings.camera;
        s->radiusM = re->radius > 0.0f ? re->radius : estimatedRadius;
        s->scene.studioBounds = settings.scene.studioBounds;
        if (scene)  // the simulation's world, as it was added when the view opened
            if (auto world = simulationGeometry(*scene); world) addGeometry(*s, std::move(*world), re->cutAway == "on");
        std::string set;
        for (const std::string& c : changedOptions(look, *re)) set += (set.empty() ? "" : " ") + c;
        if (!set.empty()) std::cerr << "meniscus: set " << set << "\n";
        model.message = set.empty() ? model.message : "set " + set;
        look = *re;
        settings = std::move(*s);
    };

    // A scene file brings its settings; any other path is a new input shown with the same look.
    const auto openPath = [&](const std::string& path) {
        auto next = isJsonFile(path) ? loadSceneFile(path) : Result<RenderJob>(look);
        if (next && !isJsonFile(path)) {
            next->input = path;
            next->moreFluids.clear();
            next->eye.reset();
            next->target.reset();
        }
        const Status st = next ? open(*next, std::nullopt) : Status(next.error());
        model.message = st ? "showing " + path : st.error().describe();
        std::cerr << "meniscus: " << (st ? "" : "error: ") << model.message << "\n";
        if (st && isJsonFile(path)) model.scenePath = path;
    };
    const auto copyTheCamera = [&] {
        const std::string line = cameraOptions(settings.camera, look.up);
        std::cout << line << std::endl;
        win.setClipboard(line);
        model.message = "copied " + line;
    };

    // The shown frame's DualSPHysics boundary particles (--boundary-particles,
    // prepareBoundary), taken out once per frame, look and geometry.
    const auto refreshBoundary = [&]() -> Status {
        if (!current) return okStatus();
        if (current != boundary.of || settings.geometry != boundary.base ||
            look.boundaryParticles != boundary.mode || look.cutAway != boundary.cutAway) {
            boundary = {current, settings.geometry, look.boundaryParticles, look.cutAway, current,
                        settings.geometry};
            if (look.boundaryParticles != "liquid" && dualSphysicsTypeAttribute(*current)) {  // else no copy
                auto liquid = std::make_shared<ParticleSet>(*current);
                const std::string name = prefetch ? prefetch->frames().name(index) : std::string("the frame");
                auto geometry = prepareBoundary(*liquid, look, settings.geometry, name);
                if (!geometry) return geometry.error();
                boundary.liquid = std::move(liquid);
                boundary.geometry = std::move(*geometry);
                const std::size_t own = settings.geometry ? settings.geometry->objects.size() : 0;
                if (!wallsHidden.empty() && boundary.geometry->objects.size() > own) {
                    auto shown = std::make_shared<SceneGeometry>(*boundary.geometry);
                    for (std::size_t k = own; k < shown->objects.size(); ++k)
                        if (wallsHidden.count(shown->objects[k].name)) shown->objects[k].visible = false;
                    boundary.geometry = std::move(shown);
                }
            }
        }
        return okStatus();
    };

    // The scene geometry's objects as the panel shows them: a new list of
    // objects is listed all as the settings have them; an object unticked
    // stays hidden when the look changes (which reads the geometry again).
    // The list is the options' objects (settings.geometry), then the shown
    // frame's DualSPHysics walls (prepareBoundary puts them after those), which
    // stay hidden by name (wallsHidden) from frame to frame.
    const auto applyVisibility = [&]() -> bool {
        const bool walls = boundary.geometry && boundary.base == settings.geometry;
        const SceneGeometry* listed = walls ? boundary.geometry.get() : settings.geometry.get();
        if (!listed) {
            model.geometryNames.clear();
            model.geometryShown.clear();
            return false;
        }
        const std::vector<GeometryObject>& objects = listed->objects;
        const std::size_t own = settings.geometry ? settings.geometry->objects.size() : 0;
        std::vector<std::string> names;
        for (const GeometryObject& g : objects) names.push_back(g.name);
        if (names != model.geometryNames) {
            model.geometryNames = std::move(names);
            model.geometryShown.clear();
            for (const GeometryObject& g : objects) model.geometryShown.push_back(g.visible ? 1 : 0);
            return false;
        }
        bool same = true;
        for (std::size_t k = 0; k < objects.size(); ++k) same = same && objects[k].visible == (model.geometryShown[k] != 0);
        if (same) return false;
        auto shown = settings.geometry ? std::make_shared<SceneGeometry>(*settings.geometry) : nullptr;
        for (std::size_t k = 0; k < objects.size(); ++k) {
            const bool visible = model.geometryShown[k] != 0;
            if (visible == objects[k].visible) continue;
            std::cerr << "meniscus: " << (visible ? "showing " : "hiding ") << objects[k].name << "\n";
            if (k < own) {
                shown->objects[k].visible = visible;
                continue;
            }
            if (visible) wallsHidden.erase(objects[k].name);
            else wallsHidden.insert(objects[k].name);
            boundary.of = nullptr;  // made again at the next draw
        }
        settings.geometry = std::move(shown);  // the walls are made again over it, hidden as the panel says
        return true;
    };

    bool stale = true;  // the frame on the backend does not show the current particles, camera and size
    int rendered = 0;
    long liveNumber = -1;      // the simulated frame on screen
    bool liveRunning = true;   // as the title last said
    int liveShown = 0;         // simulated frames shown
    std::size_t scripted = 0;  // events of the script replayed so far
    int scriptWait = 0;        // frames a scripted click has waited for its widget
    using Clock = std::chrono::steady_clock;
    Clock::time_point nextFrameDue = Clock::now(), lastShown = Clock::now();
    while (!win.shouldClose()) {
        if (auto st = refreshBoundary(); !st) return fail(st.error().describe());  // the walls listed from the first frame
        if (applyVisibility()) stale = true;
        WindowInput in = win.takeInput();
        // What the panels take is theirs (a script's events are meant for the picture).
        if (ui && panels && ui->wantsMouse()) in.drag = glm::dvec2(0.0), in.scroll = 0.0;
        if (ui && ui->wantsKeyboard()) in.keys.clear();  // typing a file name
        if (scripted < script->size()) {  // as if the user had done it during the last frame
            const ScriptEvent& e = (*script)[scripted];
            if (!e.widget.empty()) {
                if (!ui) return failUsage("--input-script: click:" + e.widget + " needs the panels (a build with Dear ImGui)");
                if (ui->scriptPointer(e.widget, e.at, e.down)) {
                    ++scripted;
                    scriptWait = 0;
                } else if (++scriptWait > kScriptWidgetFrames) {
                    return failUsage("--input-script: no widget labelled '" + e.widget + "' is shown");
                }
            } else {
                ++scripted;
                in.drag += e.in.drag;
                in.scroll += e.in.scroll;
                in.keys.insert(in.keys.end(), e.in.keys.begin(), e.in.keys.end());
                in.dropped.insert(in.dropped.end(), e.in.dropped.begin(), e.in.dropped.end());
            }
            in.any = true;
        }
        if (in.any) uiFrames = kUiSettleFrames;
        bool quit = false, copyCamera = false;
        const std::size_t count = prefetch ? prefetch->frames().count() : 1;
        for (Key key : in.keys) {
            quit |= key == Key::Escape || key == Key::Q;
            if (key == Key::Tab) panels = !panels;
            if (key == Key::H || key == Key::F1) model.showHelp = !model.showHelp;
            if (key == Key::C) copyCamera = true;
            if (key == Key::Space && count > 1) model.playing = !model.playing;
            if ((key == Key::Left || key == Key::Right) && count > 1) {
                show(key == Key::Right ? (index + 1) % count : (index + count - 1) % count);
                stale = true;
            }
        }
        if (quit) break;
        for (const std::string& path : in.dropped) {
            openPath(path);
            stale = true;
        }
        if (model.playing && count > 1 && Clock::now() >= nextFrameDue) {
            // The next frame once it has been read; playback waits for the reader rather than the window.
            const std::size_t next = (index + 1) % count;
            if (next == 0 && !model.loop) {
                model.playing = false;
            } else if (prefetch->get(next)) {
                show(next);
                stale = true;
                const auto period = std::chrono::duration<double>(1.0 / (look.fps * double(model.speed)));
                // At the sequence's rate, or as fast as the frames come when drawing is slower.
                nextFrameDue = std::max(nextFrameDue + std::chrono::duration_cast<Clock::duration>(period),
                                        Clock::now());
            }
        }
        if (live) {
            // The newest finished frame, if it is not on screen yet (running
            // read first: once it is false, latest() is the last frame).
            const bool running = live->running();
            const LiveSimulation::Frame f = live->latest();
            if (auto e = live->error()) return fail(Error{o.simulate, e->describe()}.describe());
            if (f.number != liveNumber || running != liveRunning) win.setTitle(liveTitle(o, *scene, f, running));
            liveRunning = running;
            if (f.number != liveNumber) {
                current = f.particles;
                liveNumber = f.number;
                ++liveShown;
                stale = true;
                if (!tty) std::cerr << "meniscus: showing t = " << f.time << " s (" << current->size() << " particles)\n";
            }
        }
        if (in.drag != glm::dvec2(0.0) || in.scroll != 0.0) {
            // The scene follows the cursor: dragging right turns the camera left.
            settings.camera = orbitCamera(settings.camera, -kDegreesPerDragUnit * float(in.drag.x),
                                          kDegreesPerDragUnit * float(in.drag.y),
                                          std::pow(kZoomPerWheelStep, float(in.scroll)));
            stale = true;
        }
        if (copyCamera) copyTheCamera();
        const glm::ivec2 full = win.framebufferSize();
        const Area area = pictureArea();
        const glm::ivec2 size = area.size;
        if (size.x > 0 && size.y > 0) {  // 0 x 0 while minimised: nothing to draw
            if (size.x != settings.camera.width || size.y != settings.camera.height) {
                settings.camera.width = size.x;
                settings.camera.height = size.y;
                stale = true;
            }
            if (stale || (o.frames > 0 && !live)) {
                settings.frameIndex = live ? std::int64_t(liveNumber) : std::int64_t(index);  // the noise's turbulence
                if (auto st = refreshBoundary(); !st) return fail(st.error().describe());
                RenderSettings drawn = settings;
                drawn.geometry = boundary.geometry;
                const auto start = Clock::now();
                if (auto st = renderer.draw(ParticleView::of(*boundary.liquid), drawn,
                                            ui && panels ? &model.stages : nullptr);
                    !st)
                    return fail(st.error());
                const auto end = Clock::now();
                model.drawMs = std::chrono::duration<double, std::milli>(end - start).count();
                const double gap = std::chrono::duration<double>(end - lastShown).count();
                model.framesPerSecond = gap > 0.0 ? 0.8 * model.framesPerSecond + 0.2 / gap : model.framesPerSecond;
                lastShown = end;
                ++rendered;
                stale = false;
                in.damaged = true;
            }
            if (in.damaged || (ui && uiFrames > 0)) {
                if (auto st = renderer.present(full.x, full.y, area.left); !st) return fail(st.error());
                if (ui) {
                    model.look = look;
                    model.radiusM = settings.radiusM;
                    model.camera = settings.camera;
                    model.frame = index;
                    model.frameCount = count;
                    // The frames shown are the reader's (the input's were moved into it).
                    const std::vector<std::filesystem::path>* shown = prefetch ? &prefetch->frames().files : nullptr;
                    model.frameNumber =
                        shown && index < shown->size() ? frameNumberOf((*shown)[prefetch->frames().source(index)]) : -1;
                    const UiRequests req = ui->frame(model, panels);
                    if (req.lookChanged) {
                        applyLook(model.look);
                        stale = true;
                    }
                    if (req.fovChanged) {
                        settings.camera.fovYDegrees = model.camera.fovYDegrees;
                        stale = true;
                    }
                    if (req.seek >= 0 && prefetch && std::size_t(req.seek) != index) {
                        show(std::size_t(req.seek));
                        stale = true;
                    }
                    if (req.resetCamera) {
                        settings.camera = homeCamera;
                        stale = true;
                    }
                    if (req.copyCamera) copyTheCamera();
                    if (req.save) {
                        const Status st = saveSceneFile(model.scenePath, look, settings.camera);
                        model.message = st ? "saved " + model.scenePath : st.error().describe();
                        std::cerr << "meniscus: " << (st ? "" : "error: ") << model.message << "\n";
                    }
                    if (req.load) {
                        openPath(model.scenePath);
                        stale = true;
                    }
                    if (uiFrames > 0) --uiFrames;
                }
                win.swapBuffers();
            }
        }
        // With --frames, a live view counts new simulated frames and ends with the simulation.
        const bool enough = live ? liveShown >= o.frames || !liveRunning : rendered >= o.frames;
        if (o.frames > 0 && enough && scripted >= script->size() && !stale) break;
        // A running simulation wakes the loop with each frame; otherwise --frames, the panels settling,
        // or playback keep it going.
        if ((o.frames > 0 && !(live && liveRunning && scripted >= script->size())) || stale || (ui && uiFrames > 0))
            win.pollEvents();
        else if (model.playing)
            win.waitEvents(std::max(0.0, std::chrono::duration<double>(nextFrameDue - Clock::now()).count()));
        else
            win.waitEvents();
    }
    if (live && live->running()) {
        live->stop();
        std::cerr << "meniscus: stopped the simulation at t = " << live->latest().time << " s\n";
    }

    // The back buffer is undefined after a swap: draw the last frame again and read that.
    const glm::ivec2 size = win.framebufferSize();
    const Area area = pictureArea();
    if (!o.screenshot.empty()) {  // the picture alone, beside the panels
        if (auto st = renderer.present(size.x, size.y, area.left); !st) return fail(st.error());
        if (auto st = writePng(o.screenshot, cropColumns(win.readPixels(), area.left, area.size.x), false); !st)
            return fail(st.error());
        std::cerr << "meniscus: wrote " << o.screenshot << "\n";
    }
    if (!o.screenshotWindow.empty()) {
        if (auto st = renderer.present(size.x, size.y, area.left); !st) return fail(st.error());
        if (ui) ui->frame(model, panels);
        if (auto st = writePng(o.screenshotWindow, win.readPixels(), false); !st) return fail(st.error());
        std::cerr << "meniscus: wrote " << o.screenshotWindow << "\n";
    }
    return 0;
}

#endif

}  // namespace meniscus::app
