// libFuzzer target: ParaView collections (.pvd, src/io/pvd.cpp), parsePvd.
// Beyond fuzz_reader.h's promises for errors: a result lists at least one
// file, with one finite timestep and one part per file, in ascending timestep
// order, every file joined to the base folder unless absolute.
#include <cmath>

#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace meniscus;
    const std::string name = "fuzz.pvd";
    const auto r = parsePvd(ByteView(data, size), name, "base");
    if (!fuzz::checkError(r, name)) return 0;
    const PvdCollection& c = r.value();
    if (c.files.empty()) fuzz::broken("a collection with no files", name);
    if (c.times.size() != c.files.size() || c.parts.size() != c.files.size())
        fuzz::broken("not one timestep and part per file", name);
    for (std::size_t i = 0; i < c.times.size(); ++i) {
        if (!std::isfinite(c.times[i])) fuzz::broken("a non-finite timestep", name);
        if (i > 0 && !(c.times[i - 1] < c.times[i])) fuzz::broken("timesteps not strictly ascending", name);
        if (c.parts[i] < 0) fuzz::broken("a negative part", name);
        if (!c.files[i].is_absolute() && *c.files[i].begin() != "base")
            fuzz::broken("a relative file not in the base folder", c.files[i].string());
    }
    return 0;
}
