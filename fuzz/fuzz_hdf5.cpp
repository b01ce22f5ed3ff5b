// libFuzzer target: HDF5 particle files opened from memory (HDF5's core
// driver with a file image): H5Part steps (src/io/h5part.cpp) and PySPH
// output (src/io/pysph_hdf5.cpp). What it checks is Meniscus' own code: the
// layouts, the size checks before allocating, the error paths; HDF5's own
// parsing of damaged metadata is exercised too, and a crash inside libhdf5
// shows up here like any other (docs/sanitizers.md).
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Hdf5, "fuzz.h5part");
}
