// Houdini classic BGEO, version 5, as written by partio (wdas/partio,
// src/lib/io/BGEO.cpp, writeBGEO/readBGEO): optionally gzip-compressed, then
// big-endian throughout:
//   int32 magic 'Bgeo', char 'V', int32 version (5), nPoints, nPrims,
//   nPointGroups, nPrimGroups, nPointAttrib, nVertexAttrib, nPrimAttrib, nAttrib;
//   per point attribute: uint16 nameLen, name, uint16 size, int32 type, then
//     type 0 float / 1 int / 5 vector: size x int32 defaults,
//     type 4 index (string table): int32 count, count x (uint16 len, chars);
//   nPoints records: P as 4 float32 (x, y, z, w), then each attribute's
//     `size` 4-byte words in header order;
//   primitives, groups, detail attributes and the 00 ff trailer (ignored).
// Every read is checked against the buffer; counts are validated against the
// bytes actually present before anything is allocated from them. gzip data is
// inflated in streaming passes bounded by what the header needs (a
// decompression bomb is refused without holding it in memory).
#include <algorithm>
#include <cstring>
#include <new>

#include "io/attribute_names.h"
#include "io/gzip_stream.h"
#include "io/io_util.h"
#include "io/point_memory.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

constexpr std::size_t kHeaderBytes = 4 + 1 + 9 * 4;  // magic, 'V', version + 8 counts

enum HoudiniType : std::int32_t { kFloat = 0, kInt = 1, kString = 2, kIndex = 4, kVector = 5 };

// Internal failure, turned into an Error at the parse entry; never escapes.
using io_util::fail;

// Bounds-checked big-endian reader over the file's bytes, or over a gzip
// stream inflated on demand (only as far as the reads go, at most
// kMaxPrefixBytes: the header and attribute table need no more).
class Reader {
public:
    explicit Reader(ByteView data) : data_(data) {}
    explicit Reader(InflateStream* stream) : stream_(stream) {}

    std::size_t pos() const { return pos_; }
    std::size_t remaining() const { return data_.size() - pos_; }
    const std::uint8_t* here() const { return data_.data() + pos_; }

    void need(std::size_t n, const std::string& what) {
        prefetch(n);
        if (n > remaining())
            fail("truncated " + what + ": needs " + std::to_string(n) + " bytes at offset " + std::to_string(pos_) +
                 ", file has only " + std::to_string(remaining()) + " left");
    }
    // Makes up to n bytes available (fewer only at the end of the data).
    void prefetch(std::size_t n) {
        if (n > remaining() && stream_ && !stream_->ended()) pull(n - remaining());
    }
    void skip(std::size_t n, const std::string& what) {
        need(n, what);
        pos_ += n;
    }
    std::uint32_t u32(const std::string& what) {
        need(4, what);
        const std::uint32_t v = load32(here());
        pos_ += 4;
        return v;
    }
    std::int32_t i32(const std::string& what) { return std::int32_t(u32(what)); }
    std::uint16_t u16(const std::string& what) {
        need(2, what);
        const std::uint16_t v = std::uint16_t((data_[pos_] << 8) | data_[pos_ + 1]);
        pos_ += 2;
        return v;
    }
    std::uint8_t u8(const std::string& what) {
        need(1, what);
        return data_[pos_++];
    }
    std::string str(std::size_t n, const std::string& what) {
        need(n, what);
        std::string s(reinterpret_cast<const char*>(here()), n);
        pos_ += n;
        return s;
    }

    static std::uint32_t load32(const std::uint8_t* p) {
        return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) |
               std::uint32_t(p[3]);
    }

private:
    static constexpr std::size_t kMaxPrefixBytes = std::size_t(64) << 20;

    // Inflates at least `more` further bytes (in 64 KiB steps) into buf_.
    void pull(std::size_t more) {
        const std::size_t want = std::max<std::size_t>(more, 64 * 1024);
        if (buf_.size() + more > kMaxPrefixBytes)
            fail("header and attribute table take more than 64 MiB; not a particle file");
        const std::size_t old = buf_.size();
        buf_.resize(std::min(old + want, kMaxPrefixBytes));
        auto got = stream_->read(buf_.data() + old, buf_.size() - old);
        if (!got) fail(got.error().message);
        buf_.resize(old + *got);
        data_ = buf_;
    }

    ByteView data_;
    std::size_t pos_ = 0;
    InflateStream* stream_ = nullptr;
    std::vector<std::uint8_t> buf_;  // the inflated prefix, when reading a stream
};

struct Header {
    std::int32_t version = 0, nPoints = 0, nPrims = 0, nPointGroups = 0, nPrimGroups = 0;
    std::int32_t nPointAttrib = 0, nVertexAttrib = 0, nPrimAttrib = 0, nAttrib = 0;
};

struct AttrInfo {
    std::string name;
    int size = 0;            // 4-byte words per point
    std::int32_t type = 0;   // Houdini type code
};

void checkMagic(ByteView data) {
    static const std::uint8_t magic[4] = {'B', 'g', 'e', 'o'};
    static const std::uint8_t jsonMagic[4] = {0x7f, 'N', 'S', 'J'};
    const std::size_t n = std::min<std::size_t>(data.size(), 4);
    if (n == 4 && std::memcmp(data.data(), jsonMagic, 4) == 0)
        fail("new-style (binary JSON) BGEO is not supported; only classic BGEO v5 (as partio writes, or "
             "Houdini's .bhclassic) can be read");
    if (n > 0 && std::memcmp(data.data(), magic, n) != 0)
        fail("bad magic: not a BGEO file (expected 'Bgeo' or gzip data)");
    if (data.size() < kHeaderBytes)
        fail("truncated header: BGEO header needs " + std::to_string(kHeaderBytes) + " bytes, file has " +
             std::to_string(data.size()));
}

Header readHeader(Reader& in) {
    in.skip(4, "header");  // magic, checked already
    const std::uint8_t v = in.u8("header");
    if (v != 'V') fail("bad BGEO header: expected 'V' after the magic");
    Header h;
    h.version = in.i32("header");
    if (h.version != 5)
        fail("unsupported BGEO version " + std::to_string(h.version) + " (only classic version 5 is supported)");
    h.nPoints = in.i32("header");
    h.nPrims = in.i32("header");
    h.nPointGroups = in.i32("header");
    h.nPrimGroups = in.i32("header");
    h.nPointAttrib = in.i32("header");
    h.nVertexAttrib = in.i32("header");
    h.nPrimAttrib = in.i32("header");
    h.nAttrib = in.i32("header");
    if (h.nPoints < 0) fail("bad point count " + std::to_string(h.nPoints) + " in header");
    if (h.nPointAttrib < 0) fail("bad point attribute count " + std::to_string(h.nPointAttrib) + " in header");
    return h;
}

// One entry of the point attribute table.
AttrInfo readAttributeDef(Reader& in, int index) {
    const std::string what = "attribute table (entry " + std::to_string(index + 1) + ")";
    AttrInfo a;
    const std::uint16_t nameLen = in.u16(what);
    a.name = in.str(nameLen, what);
    a.size = in.u16(what);
    a.type = in.i32(what);
    if (a.name.empty()) fail("attribute " + std::to_string(index + 1) + " has an empty name");
    if (a.size == 0) fail("attribute '" + a.name + "' has size 0");
    switch (a.type) {
        case kFloat:
        case kInt:
        case kVector:
            in.skip(std::size_t(a.size) * 4, what + " defaults");
            break;
        case kIndex: {
            const std::int32_t count = in.i32(what);
            if (count < 0) fail("attribute '" + a.name + "' has a negative string table size");
            for (std::int32_t i = 0; i < count; ++i) in.skip(in.u16(what), what + " string table");
            break;
        }
        case kString:
            fail("attribute '" + a.name + "' has type 'string', which classic BGEO readers do not support");
        default:
            fail("attribute '" + a.name + "' has unknown Houdini type " + std::to_string(a.type));
    }
    return a;
}

std::vector<AttrInfo> readAttributeTable(Reader& in, const Header& h) {
    std::vector<AttrInfo> attrs;
    for (int i = 0; i < h.nPointAttrib; ++i) attrs.push_back(readAttributeDef(in, i));  // each read is checked
    return attrs;
}

std::size_t recordWords(const std::vector<AttrInfo>& attrs) {
    std::size_t words = 4;  // P = x, y, z, w
    for (const auto& a : attrs) words += std::size_t(a.size);
    return words;
}

// Bytes allocatePoints holds per point: the position (12), each float
// component 4 and each integer one 8 (Attribute::ints is int64).
std::uint64_t heldBytesPerPoint(const std::vector<AttrInfo>& attrs) {
    std::uint64_t bytes = sizeof(glm::vec3);
    for (const auto& a : attrs)
        bytes += std::uint64_t(a.size) * (a.type == kInt || a.type == kIndex ? sizeof(std::int64_t) : sizeof(float));
    return bytes;
}

// The particle set with every array sized for n points (called only once the
// bytes for n points are known to exist, and refused when they do not fit in
// the memory budget).
ParticleSet allocatePoints(std::size_t n, const std::vector<AttrInfo>& attrs) {
    io_util::checkPointMemory(n, heldBytesPerPoint(attrs));
    ParticleSet set;
    set.positions.resize(n);
    for (const auto& a : attrs) {
        Attribute attr;
        attr.name = a.name;  // canonical names come after decoding (applyCanonicalNames)
        attr.components = a.size;
        if (a.type == kInt || a.type == kIndex) {
            attr.type = AttributeType::Int;
            attr.ints.resize(n * std::size_t(a.size));
        } else {
            attr.type = AttributeType::Float;
            attr.floats.resize(n * std::size_t(a.size));
        }
        set.attributes.push_back(std::move(attr));
    }
    return set;
}

// Decodes `count` records starting at p into points first .. first+count-1.
void decodeRecords(const std::uint8_t* p, std::size_t first, std::size_t count, ParticleSet& set) {
    for (std::size_t i = first; i < first + count; ++i) {
        float xyz[3];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t bits = Reader::load32(p + 4 * k);
            std::memcpy(&xyz[k], &bits, 4);
        }
        set.positions[i] = glm::vec3(xyz[0], xyz[1], xyz[2]);
        p += 16;
        for (auto& attr : set.attributes) {
            const std::size_t c = std::size_t(attr.components);
            for (std::size_t k = 0; k < c; ++k, p += 4) {
                const std::uint32_t bits = Reader::load32(p);
                if (attr.type == AttributeType::Int)
                    attr.ints[i * c + k] = std::int32_t(bits);
                else
                    std::memcpy(&attr.floats[i * c + k], &bits, 4);
            }
        }
    }
}

[[noreturn]] void failRoom(const Header& h, std::size_t recordBytes, std::uint64_t room) {
    fail("truncated point data: header says " + std::to_string(h.nPoints) + " points of " +
         std::to_string(recordBytes) + " bytes, file has room for only " + std::to_string(room));
}

ParticleSet readPoints(Reader& in, const Header& h, const std::vector<AttrInfo>& attrs) {
    const std::size_t recordBytes = recordWords(attrs) * 4;
    const std::size_t room = in.remaining() / recordBytes;
    if (std::size_t(h.nPoints) > room) failRoom(h, recordBytes, room);
    const std::size_t n = std::size_t(h.nPoints);
    ParticleSet set = allocatePoints(n, attrs);
    decodeRecords(in.here(), 0, n, set);
    in.skip(n * recordBytes, "point data");
    // Primitives, groups, detail attributes and the 00 ff trailer follow; a
    // particle file needs none of them.
    return set;
}

ParticleSet parseDecompressed(ByteView data) {
    checkMagic(data);
    Reader in(data);
    const Header h = readHeader(in);
    const std::vector<AttrInfo> attrs = readAttributeTable(in, h);
    return readPoints(in, h, attrs);
}

template <class T>
T orFail(Result<T> r) {
    if (!r) fail(r.error().message);
    return std::move(*r);
}

// Bytes a particle file may legitimately hold after its points (primitives,
// point groups as bitmasks, detail attributes, the trailer).
std::uint64_t tailAllowance(const Header& h) {
    return (std::uint64_t(16) << 20) + std::uint64_t(h.nPoints) * std::uint64_t(std::max(h.nPointGroups, 1));
}

// gzip-compressed BGEO in two streaming passes, so the inflated file is never
// held: the first checks the stream holds the points the header claims and
// ends within tailAllowance after them (a bomb is refused after inflating no
// more than that, keeping nothing); the second decodes the points straight
// into arrays of the final size. Peak memory: the output plus 1 MiB.
ParticleSet parseCompressed(ByteView gz, const std::string& name) {
    InflateStream first(gz, name);
    Reader in(&first);
    in.prefetch(kHeaderBytes);
    checkMagic({in.here(), in.remaining()});
    const Header h = readHeader(in);
    const std::vector<AttrInfo> attrs = readAttributeTable(in, h);
    const std::size_t tableEnd = in.pos();
    const std::size_t recordBytes = recordWords(attrs) * 4;
    const std::uint64_t n = std::uint64_t(h.nPoints);

    // No deflate stream expands more than kMaxDeflateRatio: a count beyond
    // that is refused before inflating anything more.
    const std::uint64_t possible = kMaxDeflateRatio * std::uint64_t(gz.size());
    if (n > possible / recordBytes) failRoom(h, recordBytes, possible / recordBytes);
    const std::uint64_t pointBytes = n * recordBytes;

    // Pass 1: are the points there, and does the stream end soon after?
    const std::uint64_t buffered = in.remaining();
    if (pointBytes > buffered) {
        const std::uint64_t got = orFail(first.skip(pointBytes - buffered));
        if (got < pointBytes - buffered) failRoom(h, recordBytes, (buffered + got) / recordBytes);
    }
    const std::uint64_t allowance = tailAllowance(h);
    const std::uint64_t pastPoints = buffered > pointBytes ? buffered - pointBytes : 0;
    if (pastPoints < allowance) orFail(first.skip(allowance - pastPoints));
    if (!first.ended())
        fail("gzip data inflates to more than its header needs (" + std::to_string(tableEnd + pointBytes) +
             " bytes for " + std::to_string(n) + " points, plus " + std::to_string(allowance) +
             " allowed after them); refusing it as a decompression bomb or a corrupt file");

    // Pass 2: decode, a chunk of records at a time.
    InflateStream second(gz, name);
    orFail(second.skip(tableEnd));
    ParticleSet set = allocatePoints(std::size_t(n), attrs);
    const std::size_t perChunk = std::max<std::size_t>(1, (std::size_t(1) << 20) / recordBytes);
    std::vector<std::uint8_t> chunk(std::min<std::uint64_t>(n, perChunk) * recordBytes);
    for (std::size_t i = 0; i < n; i += perChunk) {
        const std::size_t count = std::min<std::size_t>(perChunk, std::size_t(n) - i);
        if (orFail(second.read(chunk.data(), count * recordBytes)) != count * recordBytes)
            fail("gzip stream changed between passes");  // cannot happen: the same bytes inflate the same
        decodeRecords(chunk.data(), i, count, set);
    }
    return set;
}

}  // namespace

Result<ParticleSet> parseBgeo(ByteView data, const std::string& name) {
    return io_util::guardParse(name, "BGEO", [&]() -> Result<ParticleSet> {
        const bool gz = data.size() >= 2 && data[0] == 0x1f && data[1] == 0x8b;
        ParticleSet set = gz ? parseCompressed(data, name) : parseDecompressed(data);
        // Houdini's "v" is the velocity; the alias table every reader shares
        // (io/attribute_names.h) names it and the others.
        io_util::applyCanonicalNames(set.attributes);
        return set;
    });
}

}  // namespace meniscus
