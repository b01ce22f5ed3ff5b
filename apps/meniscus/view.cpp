// `meniscus view` (see view.h). A frame is rendered only when something it
// depends on changes (camera, window size, the frame of a sequence, a new
// frame of a live simulation, whose worker wakes the loop) and the
// loop sleeps in waitEvents between, so an idle viewer costs nothing; the last
// frame is drawn again when the window loses its contents.
#include "view.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include <unistd.h>

#if MENISCUS_HAVE_GLFW
#include "meniscus/window.h"
#endif
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/renderer.h"
#include "meniscus/sim.h"
#include "live_simulation.h"

namespace meniscus::app {

#if !MENISCUS_HAVE_GLFW

int runView(const ViewOptions&, const ParticleSet*) {
    return fail("this build has no viewer (it was configured without GLFW or without the GL backend); "
                "`meniscus render` writes images without one");
}

#else

namespace {

constexpr float kDegreesPerDragUnit = 0.3f;  // orbit per screen unit the cursor moves with the button held
constexpr float kZoomPerWheelStep = 0.9f;    // camera distance factor per wheel step away from the user
constexpr double kLiveSpeed = 1.0;  // --simulate: at most real time (simulated s per wall-clock s), so a fast scene plays

// One WindowInput per event of an input script ("drag:DX,DY;scroll:N;key:K").
Result<std::vector<WindowInput>> parseInputScript(const std::string& script) {
    std::vector<WindowInput> events;
    std::stringstream all(script);
    std::string item;
    while (std::getline(all, item, ';')) {
        if (item.empty()) continue;
        WindowInput in;
        double a = 0.0, b = 0.0;
        char end = 0;
        bool ok = true;
        if (std::sscanf(item.c_str(), "drag:%lf,%lf%c", &a, &b, &end) == 2 && std::isfinite(a) && std::isfinite(b))
            in.drag = glm::dvec2(a, b);
        else if (std::sscanf(item.c_str(), "scroll:%lf%c", &a, &end) == 1 && std::isfinite(a))
            in.scroll = a;
        else if (item == "key:left") in.keys.push_back(Key::Left);
        else if (item == "key:right") in.keys.push_back(Key::Right);
        else if (item == "key:q") in.keys.push_back(Key::Q);
        else if (item == "key:escape") in.keys.push_back(Key::Escape);
        else ok = false;
        if (!ok)
            return makeError("", "--input-script: '" + item +
                                     "' is not an event (drag:DX,DY, scroll:N, key:left|right|q|escape; separated by ;)");
        events.push_back(std::move(in));
    }
    return events;
}

std::string title(const ViewOptions& o, const Frames& frames, std::size_t index) {
    std::string t = "meniscus view: " + (frames.embedded ? std::string("demo") : o.render.input);
    if (frames.count() > 1)
        t += " (" + std::to_string(index + 1) + "/" + std::to_string(frames.count()) + ": " +
             frames.files[index].filename().string() + ")";
    return t;
}

std::string liveTitle(const ViewOptions& o, const sim::Scene& scene, const LiveSimulation::Frame& f, bool running) {
    char t[64];
    std::snprintf(t, sizeof t, "t = %.3f of %g s, %zu particles", f.time, scene.duration, f.particles->size());
    return "meniscus view: " + o.simulate.scene + " (" + t + (running ? ")" : ", done)");
}

}  // namespace

int runView(const ViewOptions& o, const ParticleSet* embedded) {
    auto parsed = settingsFromOptions(o.render);
    if (!parsed) return fail(parsed.error().describe());
    RenderSettings settings = std::move(*parsed);
    if (!o.screenshot.empty() && !isPng(o.screenshot)) return fail(o.screenshot + ": --screenshot must end in .png");
    auto script = parseInputScript(o.inputScript);
    if (!script) return fail(script.error().describe());

    // What the window shows: the frames of an input, or a scene simulated live
    // (its errors, like a bad input's, come before any window).
    Frames frames;
    std::optional<sim::Scene> scene;
    std::unique_ptr<sim::Simulator> simulator;
    if (!o.simulate.scene.empty()) {
        SimulateOptions so = o.simulate;
        so.radius = o.render.radius;  // one radius: the simulation's and the picture's
        auto read = sceneFromOptions(so);
        if (!read) return fail(read.error().describe());
        auto made = sim::Simulator::create(*read);
        if (!made) return fail(made.error().describe());
        scene = std::move(*read);
        simulator = std::move(*made);
    } else {
        auto opened = openFrames(o.render.input, embedded, o.render.hPerSpacing);
        if (!opened) return fail(opened.error().describe());
        if (auto st = opened->addFluids(o.render); !st) return fail(st.error().describe());
        auto up = upRotation(o.render.up);
        if (!up) return fail(up.error().describe());
        opened->up = *up;
        frames = std::move(*opened);
    }

    // The window first: without a display nothing else is worth doing.
    auto window = Window::create(o.render.width, o.render.height,
                                 scene ? "meniscus view: " + o.simulate.scene : title(o, frames, 0));
    if (!window)
        return fail(window.error().describe() +
                    "; meniscus view needs a display (`meniscus render` writes images without one)");
    Window& win = **window;

    // The camera is framed for the framebuffer's real size (HiDPI screens differ).
    RenderOptions sized = o.render;
    const glm::ivec2 fb = win.framebufferSize();
    if (fb.x > 0 && fb.y > 0) {
        sized.width = fb.x;
        sized.height = fb.y;
    }
    std::shared_ptr<const ParticleSet> current;  // what is on screen
    if (scene) {
        // Framed once on the domain, as `simulate --render` frames its images.
        if (auto st = fixForBox(sized, domainBounds(*scene), scene->params.radius, settings); !st)
            return fail(st.error().describe());
    } else {
        auto first = fixForSequence(sized, frames, settings);
        if (!first) return fail(first.error().describe());
        printWarnings(*first);
        current = std::make_shared<const ParticleSet>(std::move(*first));
    }

    auto made = Renderer::createOnCurrentGlContext();  // after the window, so destroyed before it
    if (!made) return fail(made.error().describe());
    Renderer renderer = std::move(*made);
    std::cerr << "meniscus: viewing on " << renderer.backendName() << ": drag to orbit, scroll to zoom, "
              << (frames.count() > 1 ? "left/right for frames, " : "") << "Esc or Q to quit\n";

    // After the window, so stopped (joined) before the window goes.
    std::optional<LiveSimulation> live;
    if (scene) {
        std::cerr << "meniscus: simulating " << o.simulate.scene << " live: " << simulator->size()
                  << " particles, r = " << scene->params.radius << " m, " << sim::solverName(scene->params.solver)
                  << ", " << scene->duration << " s at " << scene->fps << " fps\n";
        live.emplace(std::move(simulator), scene->fps, scene->duration, kLiveSpeed);
        live->start([&win] { win.wake(); });  // each new frame wakes the loop below out of waitEvents
    }
    const bool tty = ::isatty(STDERR_FILENO) == 1;

    std::size_t index = 0;
    bool stale = true;  // the frame on the backend does not show the current particles, camera and size
    int rendered = 0;
    long liveNumber = -1;      // the simulated frame on screen
    bool liveRunning = true;   // as the title last said
    int liveShown = 0;         // simulated frames shown
    std::size_t scripted = 0;  // events of the script replayed so far
    while (!win.shouldClose()) {
        WindowInput in = win.takeInput();
        if (scripted < script->size()) {  // as if the user had done it during the last frame
            const WindowInput& e = (*script)[scripted++];
            in.drag += e.drag;
            in.scroll += e.scroll;
            in.keys.insert(in.keys.end(), e.keys.begin(), e.keys.end());
        }
        bool quit = false;
        for (Key key : in.keys) {
            quit |= key == Key::Escape || key == Key::Q;
            if ((key != Key::Left && key != Key::Right) || frames.count() < 2) continue;
            const std::size_t n = frames.count();
            const std::size_t next = key == Key::Right ? (index + 1) % n : (index + n - 1) % n;
            auto set = frames.load(next);
            if (!set) {  // keep showing the frame we have
                std::cerr << "meniscus: error: " << set.error().describe() << "\n";
                continue;
            }
            printWarnings(*set);
            current = std::make_shared<const ParticleSet>(std::move(*set));
            index = next;
            win.setTitle(title(o, frames, index));
            stale = true;
        }
        if (quit) break;
        if (live) {
            // The newest finished frame, if it is not on screen yet (running
            // read first: once it is false, latest() is the last frame).
            const bool running = live->running();
            const LiveSimulation::Frame f = live->latest();
            if (auto e = live->error()) return fail(Error{o.simulate.scene, e->describe()}.describe());
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
        const glm::ivec2 size = win.framebufferSize();
        if (size.x > 0 && size.y > 0) {  // 0 x 0 while minimised: nothing to draw
            if (size.x != settings.camera.width || size.y != settings.camera.height) {
                settings.camera.width = size.x;
                settings.camera.height = size.y;
                stale = true;
            }
            if (stale || (o.frames > 0 && !live)) {
                settings.frameIndex = live ? std::int64_t(liveNumber) : std::int64_t(index);  // the noise's turbulence
                if (auto st = renderer.draw(ParticleView::of(*current), settings); !st)
                    return fail(st.error().describe());
                ++rendered;
                stale = false;
                in.damaged = true;
            }
            if (in.damaged) {
                if (auto st = renderer.present(size.x, size.y); !st) return fail(st.error().describe());
                win.swapBuffers();
            }
        }
        // With --frames, a live view counts new simulated frames and ends with the simulation.
        const bool enough = live ? liveShown >= o.frames || !liveRunning : rendered >= o.frames;
        if (o.frames > 0 && enough && scripted >= script->size()) break;
        // A running simulation wakes the loop with each frame; otherwise --frames keeps it going.
        if (o.frames > 0 && !(live && liveRunning && scripted >= script->size())) win.pollEvents();
        else win.waitEvents();
    }
    if (live && live->running()) {
        live->stop();
        std::cerr << "meniscus: stopped the simulation at t = " << live->latest().time << " s\n";
    }

    if (!o.screenshot.empty()) {
        // The back buffer is undefined after a swap: draw the last frame again and read that.
        const glm::ivec2 size = win.framebufferSize();
        if (auto st = renderer.present(size.x, size.y); !st) return fail(st.error().describe());
        if (auto st = writePng(o.screenshot, win.readPixels(), false); !st) return fail(st.error().describe());
        std::cerr << "meniscus: wrote " << o.screenshot << "\n";
    }
    return 0;
}

#endif

}  // namespace meniscus::app
