// libFuzzer target: gzip-compressed BGEO, the form SPlisHSPlasH (partio) writes.
// The input is inflated by inflateGzip() (src/io/gzip.cpp: header detection,
// concatenated members, the output cap) and checked like a parse; what it
// inflates to then goes through the BGEO reader. Mutating compressed bytes
// mostly exercises the inflater; fuzz_bgeo mutates the BGEO structure itself.
#include "fuzz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace meniscus;
    const std::string name = "fuzz.bgeo.gz";
    auto raw = inflateGzip(ByteView(data, size), name);
    if (!fuzz::checkError(raw, name)) return 0;
    return fuzz::fuzzParticles(raw.value().data(), raw.value().size(), ParticleFormat::Bgeo, name);
}
