// `import meniscus`: the extension module meniscus._meniscus.
// The package's __init__.py re-exports everything here; the stubs are
// python/meniscus/__init__.pyi. Errors: ValueError for bad arguments and
// arrays, OSError for files, RuntimeError when the pipeline fails while it
// runs (arrays.h).
#include <pybind11/pybind11.h>

#include "module.h"

PYBIND11_MODULE(_meniscus, m) {
    m.doc() = "Meniscus: SPH particle fluids to liquid images, meshes and simulations (C++ core).";
    m.attr("__version__") = MENISCUS_VERSION;
    meniscus::py::bindRead(m);
    meniscus::py::bindRender(m);
    meniscus::py::bindMeshSim(m);
}
