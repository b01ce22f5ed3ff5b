// libFuzzer target: numpy .npz (src/io/npz.cpp): the zip archive (libzip), the
// .npy headers, and PySPH's pickled particle dicts (src/io/pickle.cpp).
//
// Mutated archives rarely get past the zip's CRC-32 checks, so the first byte
// picks what the rest is: even, a whole .npz; odd, one .npy file, which this
// target stores in a valid zip archive itself (PKWARE APPNOTE 4.3: local
// header, data, central directory, end record; method 0, "stored") as
// particles.npy (bit 1 clear: PySPH's pickled layout) or as each of x.npy,
// y.npy, z.npy (bit 1 set: plain arrays). So the .npy and pickle readers are
// fuzzed directly too.
#include <string>
#include <vector>

#include <zlib.h>

#include "fuzz_reader.h"

namespace {

void put16(std::vector<std::uint8_t>& out, unsigned v) {
    out.push_back(std::uint8_t(v));
    out.push_back(std::uint8_t(v >> 8));
}
void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    put16(out, v & 0xffff);
    put16(out, v >> 16);
}

std::vector<std::uint8_t> storedZip(const std::vector<std::string>& names, const std::uint8_t* data, std::size_t size) {
    const std::uint32_t crc = std::uint32_t(crc32(0L, data, uInt(size)));
    std::vector<std::uint8_t> out, central;
    for (const std::string& name : names) {
        const std::uint32_t offset = std::uint32_t(out.size());
        for (std::vector<std::uint8_t>* h : {&out, &central}) {
            const bool c = h == &central;
            put32(*h, c ? 0x02014b50 : 0x04034b50);
            if (c) put16(*h, 20);  // made by
            put16(*h, 20);         // needed to extract
            put16(*h, 0);          // flags
            put16(*h, 0);          // method: stored
            put16(*h, 0);          // time
            put16(*h, 0x21);       // date 1980-01-01
            put32(*h, crc);
            put32(*h, std::uint32_t(size));
            put32(*h, std::uint32_t(size));
            put16(*h, unsigned(name.size()));
            put16(*h, 0);  // extra
            if (c) {
                put16(*h, 0);  // comment
                put16(*h, 0);  // disk
                put16(*h, 0);  // internal attributes
                put32(*h, 0);  // external attributes
                put32(*h, offset);
            }
            h->insert(h->end(), name.begin(), name.end());
        }
        out.insert(out.end(), data, data + size);
    }
    const std::uint32_t centralOffset = std::uint32_t(out.size());
    out.insert(out.end(), central.begin(), central.end());
    put32(out, 0x06054b50);
    put16(out, 0);
    put16(out, 0);
    put16(out, unsigned(names.size()));
    put16(out, unsigned(names.size()));
    put32(out, std::uint32_t(central.size()));
    put32(out, centralOffset);
    put16(out, 0);
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0 || (data[0] & 1) == 0)
        return meniscus::fuzz::fuzzParticles(data, size, meniscus::ParticleFormat::Npz, "fuzz.npz");
    const std::vector<std::string> names = (data[0] & 2) ? std::vector<std::string>{"x.npy", "y.npy", "z.npy"}
                                                         : std::vector<std::string>{"particles.npy"};
    const std::vector<std::uint8_t> zip = storedZip(names, data + 1, size - 1);
    return meniscus::fuzz::fuzzParticles(zip.data(), zip.size(), meniscus::ParticleFormat::Npz, "fuzz.npz");
}
