// A desktop window with its own OpenGL 4.3 core context, through GLFW, for the
// viewer (`meniscus view`) and any application that shows frames live
// (Renderer::createOnCurrentGlContext + present). Implemented in src/gl/
// (meniscus_gl, built when GL and GLFW are found: MENISCUS_HAVE_WINDOW in the
// installed package). This header includes neither GLFW nor GL, so callers
// never see them.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/ext/vector_uint4_sized.hpp>
#include <glm/glm.hpp>

#include "meniscus/result.h"
#include "meniscus/types.h"

struct GLFWwindow;

namespace meniscus {

// The keys a viewer reacts to; every other key is Other.
enum class Key { Escape, Q, Left, Right, Space, Tab, H, F1, C, Other };

// Input since the last Window::takeInput(), summed, so that events arriving
// during a slow frame are not lost.
struct WindowInput {
    glm::dvec2 drag{0.0};    // cursor movement while the left button was held (screen units, y down)
    double scroll = 0.0;     // vertical wheel steps, positive = away from the user
    std::vector<Key> keys;   // keys pressed (and auto-repeated), in order
    bool damaged = false;    // exposed or resized: the contents must be drawn again
    std::vector<std::string> dropped;  // files or folders dropped on the window, in order
    bool any = false;        // some event arrived (a viewer with panels draws them again)
};

class Window {
public:
    // Opens a width x height window (screen units) titled `title` with a GL
    // 4.3 core-profile context (a debug context sending GL errors to stderr in
    // debug builds) and makes that context current on this thread. The error,
    // never an exception or an exit, says why not: no display, GLFW could not
    // start, no GL 4.3; GLFW's own message is part of it. GLFW wants this
    // called, and the window used, on the main thread.
    static Result<std::unique_ptr<Window>> create(int width, int height, const std::string& title);

    // Anything made on the window's context (a Renderer) must be gone first.
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;

    void makeCurrent() const;
    bool shouldClose() const;  // the user closed the window (or requestClose)
    void requestClose();
    void setTitle(const std::string& title);
    void setClipboard(const std::string& text);  // the system clipboard's text

    void pollEvents();  // handles pending events and returns at once
    void waitEvents();  // sleeps until at least one event has arrived, then handles them
    void waitEvents(double timeoutSeconds);  // the same, but sleeps no longer than this
    // Wakes a waitEvents() on the main thread (an empty event). Unlike the
    // rest, may be called from any thread, while the window exists: a worker
    // that has something new to show calls it.
    void wake();
    WindowInput takeInput();  // what the events since the last call amounted to

    // Framebuffer size in pixels (not screen units: they differ on HiDPI
    // screens); 0 x 0 while minimised.
    glm::ivec2 framebufferSize() const;
    void swapBuffers();
    // The back buffer as drawn since the last swap, 8-bit RGBA with row 0 the
    // TOP row (flipped from GL's bottom-first order); waits for the GPU.
    Image<glm::u8vec4> readPixels() const;

    // GLFW's own handle, for libraries that drive GLFW themselves (the
    // viewer's Dear ImGui panels install their callbacks on it, chained to
    // this window's, so takeInput still sees every event).
    GLFWwindow* glfwHandle() const { return window_; }

    const std::string& renderer() const { return renderer_; }  // GL_RENDERER
    const std::string& version() const { return version_; }    // GL_VERSION

private:
    Window() = default;
    friend struct WindowCallbacks;
    GLFWwindow* window_ = nullptr;
    WindowInput input_;
    bool dragging_ = false;
    glm::dvec2 cursor_{0.0};
    std::string renderer_, version_;
};

}  // namespace meniscus
