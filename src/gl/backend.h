// The GL backend behind the core's Backend interface. This header includes no
// GL header: the renderer (src/render/backend_factory.cpp) includes it to make the backend.
#pragma once

#include <memory>

#include "core/backend.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Creates a headless GL 4.3 context (current on the calling thread from then
// on) and the backend on it; an error says what failed. The stages' programs
// are compiled by their drivers (the stage list's prepareStages).
Result<std::unique_ptr<Backend>> makeGlBackend();

// The same on the GL context already current on the calling thread (a
// gl::Window's), which must outlive the backend and stay current while it is
// used; only such a backend can present(). An error when that context is not
// GL 4.3 or later.
Result<std::unique_ptr<Backend>> makeGlBackendOnCurrentContext();

}  // namespace meniscus::gl
