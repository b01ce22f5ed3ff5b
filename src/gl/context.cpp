// Headless EGL context. EGL handles are kept as void* in the header so that no
// EGL/GL header leaks out of this file's translation unit.
#include "gl/context.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace meniscus::gl {

namespace {

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

std::string eglErrorText(EGLint e) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "EGL error 0x%04x", unsigned(e));
    return buf;
}

// Debug builds, or MENISCUS_GL_DEBUG set in any build: every GL error and
// warning goes to stderr as it happens; MENISCUS_GL_DEBUG=all adds the
// driver's notifications (NVIDIA's say where each buffer lives), the first
// 400 of them.
void GLAPIENTRY debugCallback(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message,
                              const void* userParam) {
    static int notes = 0;
    const bool all = userParam != nullptr;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION && (!all || ++notes > 400)) return;
    std::fprintf(stderr, "meniscus gl debug (%s): %s\n", type == GL_DEBUG_TYPE_ERROR ? "error" : "note", message);
}

struct Candidate {
    EGLDisplay display;
    std::string name;
};

// Displays to try, best first.
std::vector<Candidate> candidateDisplays() {
    std::vector<Candidate> out;
    // Client extensions (EGL 1.5 / EGL_EXT_client_extensions); null if unsupported.
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const bool platformBase = hasExtension(client, "EGL_EXT_platform_base") || epoxy_egl_version(EGL_NO_DISPLAY) >= 15;
    auto platformDisplay = [&](EGLenum platform, void* native) -> EGLDisplay {
        if (hasExtension(client, "EGL_EXT_platform_base")) return eglGetPlatformDisplayEXT(platform, native, nullptr);
        return eglGetPlatformDisplay(platform, native, nullptr);
    };
    if (platformBase && hasExtension(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY);
        if (d != EGL_NO_DISPLAY) out.push_back({d, "surfaceless"});
    }
    if (platformBase && hasExtension(client, "EGL_EXT_platform_device") && hasExtension(client, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (eglQueryDevicesEXT(16, devices, &count))
            for (EGLint i = 0; i < count; ++i) {
                EGLDisplay d = platformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i]);
                if (d != EGL_NO_DISPLAY) out.push_back({d, "device " + std::to_string(i)});
            }
    }
    EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (d != EGL_NO_DISPLAY) out.push_back({d, "default"});
    return out;
}

}  // namespace

void enableDebugOutput() {
    const char* env = std::getenv("MENISCUS_GL_DEBUG");
#ifdef NDEBUG
    if (!env || !*env) return;
#endif
    static const int kAll = 1;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, env && std::string_view(env) == "all" ? &kAll : nullptr);
}

Result<std::unique_ptr<Context>> Context::createHeadless() {
    std::string why;  // what failed on each candidate, for the error message
    auto note = [&](const std::string& name, const std::string& what) {
        why += (why.empty() ? "" : "; ") + name + ": " + what;
    };
    for (const Candidate& cand : candidateDisplays()) {
        EGLDisplay dpy = cand.display;
        EGLint major = 0, minor = 0;
        if (!eglInitialize(dpy, &major, &minor)) {
            note(cand.name, "eglInitialize failed (" + eglErrorText(eglGetError()) + ")");
            continue;
        }
        if (!eglBindAPI(EGL_OPENGL_API)) {
            note(cand.name, "no desktop OpenGL API");
            continue;
        }
        const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint nConfigs = 0;
        const bool haveConfig = eglChooseConfig(dpy, configAttribs, &config, 1, &nConfigs) && nConfigs > 0;
        const bool noConfig = hasExtension(eglQueryString(dpy, EGL_EXTENSIONS), "EGL_KHR_no_config_context");
        if (!haveConfig && !noConfig) {
            note(cand.name, "no OpenGL pbuffer config");
            continue;
        }
        const EGLint contextAttribs[] = {
            EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
#ifndef NDEBUG
            EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE,
#endif
            EGL_NONE};
        EGLContext ctx = eglCreateContext(dpy, haveConfig ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, contextAttribs);
        if (ctx == EGL_NO_CONTEXT) {
            note(cand.name, "no GL 4.3 core context (" + eglErrorText(eglGetError()) + ")");
            continue;
        }
        // Surfaceless when the driver allows it; else a 1x1 pbuffer (all our
        // rendering goes to our own framebuffers anyway).
        EGLSurface surface = EGL_NO_SURFACE;
        if (!hasExtension(eglQueryString(dpy, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context") && haveConfig) {
            const EGLint pbufferAttribs[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
            surface = eglCreatePbufferSurface(dpy, config, pbufferAttribs);
        }
        if (!eglMakeCurrent(dpy, surface, surface, ctx)) {
            note(cand.name, "eglMakeCurrent failed (" + eglErrorText(eglGetError()) + ")");
            if (surface != EGL_NO_SURFACE) eglDestroySurface(dpy, surface);
            eglDestroyContext(dpy, ctx);
            continue;
        }
        std::unique_ptr<Context> c(new Context);
        c->display_ = dpy;
        c->context_ = ctx;
        c->surface_ = surface;
        c->platform_ = cand.name;
        if (epoxy_gl_version() < 43) {
            note(cand.name, "GL version below 4.3");
            continue;  // the destructor releases it
        }
        const auto str = [](GLenum e) {
            const GLubyte* s = glGetString(e);
            return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
        };
        c->renderer_ = str(GL_RENDERER);
        c->version_ = str(GL_VERSION);
        enableDebugOutput();
        return c;
    }
    return makeError("", "cannot create a headless OpenGL 4.3 context: " + (why.empty() ? std::string("no EGL display") : why));
}

Context::~Context() {
    EGLDisplay dpy = display_;
    if (eglGetCurrentContext() == EGLContext(context_)) eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (surface_) eglDestroySurface(dpy, EGLSurface(surface_));
    eglDestroyContext(dpy, EGLContext(context_));
    // No eglTerminate: the EGLDisplay is one per process and platform, shared
    // by every context made on it; terminating it would break the others.
}

Status Context::makeCurrent() const {
    if (!eglMakeCurrent(EGLDisplay(display_), EGLSurface(surface_), EGLSurface(surface_), EGLContext(context_)))
        return makeError("", "eglMakeCurrent failed (" + eglErrorText(eglGetError()) + ")");
    return okStatus();
}

}  // namespace meniscus::gl
