// The viewer's window (see window.h). GLFW is initialised with the first
// window and terminated with the last, so a process that never opens one
// never touches the display. GLFW reports errors through a process-wide
// callback; the last message is kept and put into create()'s error.
#include "meniscus/window.h"

#include <algorithm>
#include <string>
#include <utility>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE  // GL comes from epoxy, not from GLFW's headers
#include <GLFW/glfw3.h>

#include "gl/context.h"

namespace meniscus {

namespace {

int gOpenWindows = 0;       // GLFW is initialised while this is > 0
std::string gLastGlfwError;  // GLFW's most recent error message

void onGlfwError(int, const char* description) { gLastGlfwError = description ? description : "unknown GLFW error"; }

std::string lastGlfwError() { return gLastGlfwError.empty() ? std::string("no reason given") : gLastGlfwError; }

Key keyFromGlfw(int key) {
    switch (key) {
        case GLFW_KEY_ESCAPE: return Key::Escape;
        case GLFW_KEY_Q: return Key::Q;
        case GLFW_KEY_LEFT: return Key::Left;
        case GLFW_KEY_RIGHT: return Key::Right;
        case GLFW_KEY_SPACE: return Key::Space;
        case GLFW_KEY_TAB: return Key::Tab;
        case GLFW_KEY_H: return Key::H;
        case GLFW_KEY_F1: return Key::F1;
        case GLFW_KEY_C: return Key::C;
        default: return Key::Other;
    }
}

Window* owner(GLFWwindow* w) { return static_cast<Window*>(glfwGetWindowUserPointer(w)); }

}  // namespace

// GLFW's callbacks, with access to the window's input (a friend of Window).
struct WindowCallbacks {
    static void key(GLFWwindow* w, int key, int, int action, int) {
        owner(w)->input_.any = true;
        if (action == GLFW_PRESS || action == GLFW_REPEAT) owner(w)->input_.keys.push_back(keyFromGlfw(key));
    }
    static void button(GLFWwindow* w, int button, int action, int) {
        Window* self = owner(w);
        self->input_.any = true;
        if (button != GLFW_MOUSE_BUTTON_LEFT) return;
        self->dragging_ = action == GLFW_PRESS;
        glfwGetCursorPos(w, &self->cursor_.x, &self->cursor_.y);  // a drag starts where the press was
    }
    static void cursor(GLFWwindow* w, double x, double y) {
        Window* self = owner(w);
        self->input_.any = true;
        if (self->dragging_) self->input_.drag += glm::dvec2(x, y) - self->cursor_;
        self->cursor_ = {x, y};
    }
    static void scroll(GLFWwindow* w, double, double dy) {
        owner(w)->input_.scroll += dy;
        owner(w)->input_.any = true;
    }
    static void damaged(GLFWwindow* w) {
        owner(w)->input_.damaged = true;
        owner(w)->input_.any = true;
    }
    static void dropped(GLFWwindow* w, int count, const char** paths) {
        for (int i = 0; i < count; ++i) owner(w)->input_.dropped.emplace_back(paths[i]);
        owner(w)->input_.any = true;
    }
    static void resized(GLFWwindow* w, int, int) { damaged(w); }
};

Result<std::unique_ptr<Window>> Window::create(int width, int height, const std::string& title) {
    glfwSetErrorCallback(onGlfwError);
    gLastGlfwError.clear();
    if (gOpenWindows == 0 && !glfwInit())
        return makeError("", "cannot open a window: GLFW could not start (" + lastGlfwError() + ")");
    std::unique_ptr<Window> win(new Window);
    ++gOpenWindows;  // from here the destructor balances it (and terminates GLFW after the last)

    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#ifndef NDEBUG
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
    win->window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!win->window_)
        return makeError("", "cannot open a window with an OpenGL 4.3 core context (" + lastGlfwError() + ")");
    glfwSetWindowUserPointer(win->window_, win.get());
    glfwMakeContextCurrent(win->window_);
    const auto str = [](GLenum e) {
        const GLubyte* s = glGetString(e);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    win->renderer_ = str(GL_RENDERER);
    win->version_ = str(GL_VERSION);
    if (epoxy_gl_version() < 43)  // GLFW asked for 4.3; a driver may still hand out less
        return makeError("", "the window's OpenGL context is " + win->version_ + "; 4.3 or later is needed");
    gl::enableDebugOutput();
    glfwSwapInterval(1);  // no faster than the display: a viewer has no use for torn frames

    glfwSetKeyCallback(win->window_, WindowCallbacks::key);
    glfwSetMouseButtonCallback(win->window_, WindowCallbacks::button);
    glfwSetCursorPosCallback(win->window_, WindowCallbacks::cursor);
    glfwSetScrollCallback(win->window_, WindowCallbacks::scroll);
    glfwSetWindowRefreshCallback(win->window_, WindowCallbacks::damaged);
    glfwSetFramebufferSizeCallback(win->window_, WindowCallbacks::resized);
    glfwSetDropCallback(win->window_, WindowCallbacks::dropped);
    return win;
}

Window::~Window() {
    if (window_) glfwDestroyWindow(window_);
    if (--gOpenWindows == 0) glfwTerminate();
}

void Window::makeCurrent() const { glfwMakeContextCurrent(window_); }
bool Window::shouldClose() const { return glfwWindowShouldClose(window_); }
void Window::requestClose() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void Window::setTitle(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }
void Window::setClipboard(const std::string& text) { glfwSetClipboardString(window_, text.c_str()); }
void Window::pollEvents() { glfwPollEvents(); }
void Window::waitEvents() { glfwWaitEvents(); }
void Window::waitEvents(double timeoutSeconds) { glfwWaitEventsTimeout(timeoutSeconds); }
void Window::wake() { glfwPostEmptyEvent(); }  // thread-safe (GLFW's docs)
void Window::swapBuffers() { glfwSwapBuffers(window_); }

WindowInput Window::takeInput() { return std::exchange(input_, WindowInput{}); }

glm::ivec2 Window::framebufferSize() const {
    glm::ivec2 size{0};
    glfwGetFramebufferSize(window_, &size.x, &size.y);
    return size;
}

Image<glm::u8vec4> Window::readPixels() const {
    const glm::ivec2 size = framebufferSize();
    Image<glm::u8vec4> bottomUp(size.x, size.y), out(size.x, size.y);
    if (out.empty()) return out;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.pixels.data());
    for (int y = 0; y < size.y; ++y)
        std::copy_n(&bottomUp.at(0, size.y - 1 - y), size.x, &out.at(0, y));
    return out;
}

}  // namespace meniscus
