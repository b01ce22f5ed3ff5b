// Picks the backend for a BackendChoice. The GL backend is compiled in only
// when CMake found libepoxy and EGL (MENISCUS_HAVE_GL); src/gl/backend.h
// includes no GL header, so nothing GL leaks into the core.
#include "core/backend.h"
#include "render/stages.h"

#if MENISCUS_HAVE_GL
#include "gl/backend.h"
#endif

namespace meniscus {

namespace {
[[maybe_unused]] constexpr const char* kNoGl =
    "this build has no GL backend (libepoxy or EGL were not found when it was configured)";

// Whether a GL backend's name ("gl (<GL_RENDERER>)") is a software
// rasteriser: Mesa's llvmpipe, softpipe and swrast, Windows' WARP. On those
// the CPU backend, written for the CPU, is several times as fast
// (docs/performance.md#gl-backend-on-mesa-llvmpipe-no-gpu).
[[maybe_unused]] bool softwareGl(const std::string& name) {
    for (const char* s : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer", "Basic Render Driver"})
        if (name.find(s) != std::string::npos) return true;
    return false;
}
}  // namespace

namespace {
// A GL backend with every stage's programs compiled: an error when one fails.
[[maybe_unused]] Result<std::unique_ptr<Backend>> prepared(Result<std::unique_ptr<Backend>> b) {
    if (!b) return b;
    if (auto st = prepareStages(**b); !st) return st.error();
    return b;
}
}  // namespace

Result<std::unique_ptr<Backend>> makeGlBackendOnCurrentContext() {
#if MENISCUS_HAVE_GL
    return prepared(gl::makeGlBackendOnCurrentContext());
#else
    return makeError("", kNoGl);
#endif
}

Result<std::unique_ptr<Backend>> makeBackend(BackendChoice choice, std::string* note) {
    if (choice == BackendChoice::Cpu) return makeCpuBackend();
    std::string why;
#if MENISCUS_HAVE_GL
    auto gl = prepared(gl::makeGlBackend());
    if (gl && choice == BackendChoice::Auto && softwareGl((*gl)->name())) {
        if (note)
            *note = "the only GL here is a software rasteriser, " + (*gl)->name() +
                    "; using the CPU backend, which is faster on it (--backend gl to use it anyway)";
        return makeCpuBackend();
    }
    if (gl) return std::move(*gl);
    why = gl.error().describe();
#else
    why = kNoGl;
#endif
    if (choice == BackendChoice::Gl) return makeError("", "GL backend unavailable: " + why);
    if (note) *note = "GL backend unavailable (" + why + "); using the CPU backend";
    return makeCpuBackend();
}

}  // namespace meniscus
