// Headless OpenGL 4.3+ core context through EGL (no window, no display server).
// GL entry points are loaded with libepoxy. GL headers stay inside src/gl/.
#pragma once

#include <memory>
#include <string>

#include "meniscus/result.h"

namespace meniscus::gl {

class Context {
public:
    // Creates a GL 4.3+ core-profile context and makes it current on this
    // thread. Tries, in order: the Mesa surfaceless platform, each EGL device
    // (EGL_EXT_platform_device, e.g. NVIDIA without X), then the default
    // display with a 1x1 pbuffer. An error says why none worked; never throws.
    static Result<std::unique_ptr<Context>> createHeadless();

    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // Makes this context current on the calling thread.
    Status makeCurrent() const;

    const std::string& renderer() const { return renderer_; }  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    const std::string& version() const { return version_; }    // GL_VERSION
    const std::string& platform() const { return platform_; }  // how it was made: "surfaceless", "device 0", "default"

private:
    Context() = default;
    void* display_ = nullptr;  // EGLDisplay
    void* context_ = nullptr;  // EGLContext
    void* surface_ = nullptr;  // EGLSurface, or null when surfaceless
    std::string renderer_, version_, platform_;
};

// Debug builds: sends every GL error and warning of the current context (made
// with the debug flag) to stderr as it happens. Release builds: does nothing.
// Every context the backend runs on (headless here, gl::Window) calls it.
void enableDebugOutput();

}  // namespace meniscus::gl
