// The module's areas, each bound by its own file (module.cpp calls them).
#pragma once

#include <span>

#include <glm/glm.hpp>
#include <pybind11/pybind11.h>

#include "arrays.h"
#include "meniscus/particles.h"

namespace meniscus::py {

void bindRead(pybind11::module_& m);     // read.cpp: read, sequence, demo, estimate_radius, write_png
void bindRender(pybind11::module_& m);   // render.cpp: render, Renderer, auto_camera, settings
void bindMeshSim(pybind11::module_& m);  // mesh_sim.cpp: mesh, simulate

// The radius the CLI takes when none is given (defaultRadius): the median of
// the particles' own radii when they have them, else the estimate from the
// positions. Call without the GIL held.
RadiusEstimate defaultRadiusOf(const Particles& p, std::span<const glm::vec3> points);

// The rows of `meniscus simulate`'s table simulate() takes as keywords (the
// rest are the command's files and printing).
inline constexpr const char* kSimulateKeywords[] = {"duration", "fps", "radius", "solver"};

}  // namespace meniscus::py
