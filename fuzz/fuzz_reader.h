// Shared body of the reader fuzz targets (fuzz/fuzz_<reader>.cpp): parse the
// input as one format through parseParticles(), the path every particle file
// takes, then check what the library promises for any input (include/meniscus/io.h):
//  - an error names the file it was given and says what is wrong;
//  - a result has particles, all with finite positions, and every attribute
//    holds exactly one value per particle and component.
// A broken promise aborts, which libFuzzer (and the regression driver) report
// as a failure, the same as a crash or a sanitizer error.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "meniscus/io.h"

namespace meniscus::fuzz {

[[noreturn]] inline void broken(const char* what, const std::string& detail) {
    std::fprintf(stderr, "fuzz: broken promise: %s (%s)\n", what, detail.c_str());
    std::abort();
}

// True when `r` holds a value; an error must name `name` and say something.
template <class T>
bool checkError(const Result<T>& r, const std::string& name) {
    if (r) return true;
    if (r.error().file != name) broken("the error does not name the file", r.error().describe());
    if (r.error().message.empty()) broken("the error has no message", name);
    return false;
}

inline void checkParticles(const Result<ParticleSet>& r, const std::string& name) {
    if (!checkError(r, name)) return;
    const ParticleSet& set = r.value();
    if (set.size() == 0) broken("a result with no particles", name);
    for (const auto& p : set.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            broken("a non-finite position was kept", name);
    for (const Attribute& a : set.attributes) {
        const bool isFloat = a.type == AttributeType::Float;
        const std::size_t values = isFloat ? a.floats.size() : a.ints.size();
        const std::size_t unused = isFloat ? a.ints.size() : a.floats.size();
        if (a.components <= 0 || values != set.size() * std::size_t(a.components) || unused != 0)
            broken("an attribute does not hold one value per particle and component", a.name);
    }
}

// A mesh reader's result is a whole, valid mesh (TriangleMesh::validate) with
// at least one triangle.
inline void checkMesh(const Result<TriangleMesh>& r, const std::string& name) {
    if (!checkError(r, name)) return;
    if (r->empty()) broken("a mesh with no triangles", name);
    if (Status st = r->validate(); !st) broken("an invalid mesh", st.error().message);
}

inline int fuzzParticles(const std::uint8_t* data, std::size_t size, ParticleFormat format,
                         const std::string& name) {
    checkParticles(parseParticles(ByteView(data, size), name, format), name);
    return 0;
}

}  // namespace meniscus::fuzz
