// VTK XML particle reader: UnstructuredGrid (.vtu) and PolyData (.vtp), as
// SPlisHSPlasH, ParaView and VTK's own vtkXMLUnstructuredGridWriter /
// vtkXMLPolyDataWriter write them. Only the points and their point data are
// read; cells (vertices) are ignored.
//
// Format reference: "VTK File Formats", section "XML File Formats"
// (VTK User's Guide; https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html),
// checked against files written by VTK 9.1 (tests/data/vtu/).
//
//   <VTKFile type="UnstructuredGrid|PolyData" version="0.1|1.0"
//            byte_order="LittleEndian|BigEndian" header_type="UInt32|UInt64"
//            compressor="vtkZLibDataCompressor|vtkLZ4DataCompressor|vtkLZMADataCompressor">
//                                                         (header_type absent: UInt32)
//     <UnstructuredGrid> <Piece NumberOfPoints="N"> ... several pieces are concatenated
//       <PointData> <DataArray type=".." Name=".." NumberOfComponents="c" format=".."> ...
//       <Points> <DataArray NumberOfComponents="3" ...>
//   <AppendedData encoding="raw|base64"> _<bytes> </AppendedData>
//
// Binary array layout (format="binary" and format="appended"); every header
// word is a header_type integer in the file's byte order, and so is the data:
//   uncompressed: [nbytes] [data]
//   compressed:   [nblocks] [blocksize] [lastblocksize] [csize_1 .. csize_n] [block_1 .. block_n]
//                 each block inflating to blocksize bytes, the last to
//                 lastblocksize (0 means a full block); the same layout for every
//                 compressor (vtkXMLWriter writes the header, the compressor the
//                 blocks), each block being, as VTK 9's compressors write them:
//                   zlib: one zlib stream (compress2; vtkZLibDataCompressor);
//                   LZ4:  one raw LZ4 block (LZ4_compress_fast, no frame;
//                         vtkLZ4DataCompressor reads it with LZ4_decompress_safe);
//                   LZMA: one complete .xz stream (lzma_easy_buffer_encode,
//                         CRC64 check; vtkLZMADataCompressor reads it with
//                         lzma_stream_buffer_decode).
//                 Before anything is allocated, each block's size is checked
//                 against its compressed bytes times the compressor's largest
//                 possible ratio (zlib ~1032:1, LZ4 ~255:1); for LZMA, whose
//                 ratio can reach several thousand to one, the output grows only
//                 as the stream really decodes, and the decoder's memory is capped.
// format="binary": the array's text is base64. VTK encodes an uncompressed array
//   (header + data) as one base64 stream, but a compressed array as two: the
//   header on its own (with its own '=' padding), then the blocks. We decode in
//   4-character groups, so a padded group ends one stream and the next group
//   starts the next: both layouts read the same, as in VTK's reader.
// format="appended": offset="k" counts from the byte after the '_' marker; raw
//   encoding holds the binary layout above as plain bytes, base64 encoding holds
//   it encoded as for format="binary" (offset counts characters). Raw appended
//   data is arbitrary binary, so it never goes to the XML parser: only the XML
//   before <AppendedData> is parsed (with the still open elements closed here)
//   and the arrays are read from the bytes by offset.
//
// Arrays the alias table every reader shares (io/attribute_names.h) names
// velocity (velocity, Vel, v, any case; 3 components, float), density
// (density, rho, Rhop; 1, float) and id (id, Idp; 1 component, integer or
// floats holding whole numbers) become the canonical "velocity", "density" and "id";
// every other point array is kept by name (integer types as Int, float types as
// Float). Every size, offset and count is checked against the buffer; problems
// come back as an Error naming the file, never as a crash or an exception.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <tinyxml2.h>
#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

#include "io/attribute_names.h"
#include "io/io_util.h"
#include "io/point_memory.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

// Internal failure; turned into an Error at the entry point.
using io_util::fail;

std::string str(std::uint64_t v) { return std::to_string(v); }
std::string inQuotes(std::string_view s) {
    std::string out;
    out.reserve(s.size() + 2);
    out += '\'';
    out.append(s);
    out += '\'';
    return out;
}

// ---------------------------------------------------------------- scalar types

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

struct ScalarInfo {
    std::string_view name;
    Scalar type;
    std::size_t size;  // bytes
    bool isFloat;
};

constexpr ScalarInfo kScalars[] = {
    {"Int8", Scalar::Int8, 1, false},       {"UInt8", Scalar::UInt8, 1, false},
    {"Int16", Scalar::Int16, 2, false},     {"UInt16", Scalar::UInt16, 2, false},
    {"Int32", Scalar::Int32, 4, false},     {"UInt32", Scalar::UInt32, 4, false},
    {"Int64", Scalar::Int64, 8, false},     {"UInt64", Scalar::UInt64, 8, false},
    {"Float32", Scalar::Float32, 4, true},  {"Float64", Scalar::Float64, 8, true},
};

const ScalarInfo* findScalar(std::string_view name) {
    for (const auto& s : kScalars)
        if (s.name == name) return &s;
    return nullptr;
}

// One value of type T from `p`, byte-swapped when the file's order differs from ours.
template <class T>
T loadValue(const std::uint8_t* p, bool swap) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, p, sizeof(T));
    if (swap) std::reverse(b, b + sizeof(T));
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
}

// Narrowing that saturates to +-inf instead of overflowing (undefined for doubles beyond float range).
template <class T>
float toFloat(T v) {
    if constexpr (std::is_same_v<T, double>) {
        if (v > double(std::numeric_limits<float>::max())) return std::numeric_limits<float>::infinity();
        if (v < -double(std::numeric_limits<float>::max())) return -std::numeric_limits<float>::infinity();
    }
    return float(v);
}

// `count` values of type `t` from raw bytes into out.floats or out.ints
// (out.type must already say which).
void convertValues(const std::uint8_t* p, std::size_t count, const ScalarInfo& t, bool swap, Attribute& out) {
    auto run = [&](auto tag) {
        using T = decltype(tag);
        if (out.type == AttributeType::Float) {
            out.floats.resize(count);
            for (std::size_t i = 0; i < count; ++i) out.floats[i] = toFloat(loadValue<T>(p + i * sizeof(T), swap));
        } else {
            out.ints.resize(count);
            for (std::size_t i = 0; i < count; ++i)
                out.ints[i] = std::int64_t(loadValue<T>(p + i * sizeof(T), swap));  // UInt64 above 2^63 wraps
        }
    };
    switch (t.type) {
        case Scalar::Int8: run(std::int8_t{}); break;
        case Scalar::UInt8: run(std::uint8_t{}); break;
        case Scalar::Int16: run(std::int16_t{}); break;
        case Scalar::UInt16: run(std::uint16_t{}); break;
        case Scalar::Int32: run(std::int32_t{}); break;
        case Scalar::UInt32: run(std::uint32_t{}); break;
        case Scalar::Int64: run(std::int64_t{}); break;
        case Scalar::UInt64: run(std::uint64_t{}); break;
        case Scalar::Float32: run(float{}); break;
        case Scalar::Float64: run(double{}); break;
    }
}

// ---------------------------------------------------------------- byte sources

// Where an array's binary bytes (header, then data) come from.
class ByteSource {
public:
    virtual ~ByteSource() = default;
    // Exactly n bytes, or fail naming the array as truncated.
    virtual void read(std::uint8_t* out, std::size_t n) = 0;
    // An upper bound on what read() can still deliver (for checks before allocating).
    virtual std::size_t maxBytesLeft() const = 0;
};

// Plain bytes: raw appended data.
class RawSource final : public ByteSource {
public:
    RawSource(ByteView data, std::string what) : data_(data), what_(std::move(what)) {}
    void read(std::uint8_t* out, std::size_t n) override {
        if (n > data_.size() - pos_)
            fail(what_ + ": truncated appended data (needs " + str(n) + " more bytes, " + str(data_.size() - pos_) +
                 " left)");
        if (n) std::memcpy(out, data_.data() + pos_, n);
        pos_ += n;
    }
    std::size_t maxBytesLeft() const override { return data_.size() - pos_; }

private:
    ByteView data_;
    std::size_t pos_ = 0;
    std::string what_;
};

constexpr std::int8_t kBase64Invalid = -1;
constexpr std::int8_t kBase64Pad = -2;

constexpr auto kBase64Table = [] {
    std::array<std::int8_t, 256> t{};
    for (auto& v : t) v = kBase64Invalid;
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = 0; i < 64; ++i) t[std::uint8_t(alphabet[i])] = std::int8_t(i);
    t[std::uint8_t('=')] = kBase64Pad;
    return t;
}();

bool isXmlSpace(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

// Base64 text, decoded group by group (whitespace ignored). A group with '='
// padding ends one encoded stream; the following group starts the next one, so
// separately encoded header and data (VTK's compressed layout) decode in order.
class Base64Source final : public ByteSource {
public:
    Base64Source(std::string_view text, std::string what) : text_(text), what_(std::move(what)) {}

    void read(std::uint8_t* out, std::size_t n) override {
        while (n > 0) {
            if (bufPos_ == bufLen_ && !nextGroup())
                fail(what_ + ": truncated data (base64 text ends " + str(n) + " bytes early)");
            const std::size_t take = std::min<std::size_t>(n, std::size_t(bufLen_ - bufPos_));
            std::memcpy(out, buf_ + bufPos_, take);
            bufPos_ += int(take);
            out += take;
            n -= take;
        }
    }
    std::size_t maxBytesLeft() const override {
        return std::size_t(bufLen_ - bufPos_) + (text_.size() - pos_) / 4 * 3 + 3;
    }

private:
    bool nextGroup() {
        char c[4];
        std::size_t at[4];
        int k = 0;
        while (k < 4 && pos_ < text_.size()) {
            const char ch = text_[pos_++];
            if (isXmlSpace(ch)) continue;
            at[k] = pos_ - 1;
            c[k++] = ch;
        }
        if (k == 0) return false;
        for (int i = k; i < 4; ++i) c[i] = '=';  // tolerate missing final padding
        std::int8_t v[4];
        for (int i = 0; i < 4; ++i) {
            v[i] = kBase64Table[std::uint8_t(c[i])];
            if (v[i] == kBase64Invalid) {
                const unsigned char ch = std::uint8_t(c[i]);
                std::string shown = (ch >= 0x20 && ch < 0x7f) ? inQuotes(std::string(1, char(ch)))
                                                                : "byte " + str(ch);
                fail(what_ + ": bad base64 (" + shown + " at character " + str(at[i]) + ")");
            }
        }
        if (v[0] == kBase64Pad || v[1] == kBase64Pad || (v[2] == kBase64Pad && v[3] != kBase64Pad))
            fail(what_ + ": bad base64 (misplaced '=' padding near character " + str(at[std::min(k, 4) - 1]) + ")");
        const std::uint32_t bits = (std::uint32_t(v[0]) << 18) | (std::uint32_t(v[1]) << 12) |
                                   (std::uint32_t(v[2] == kBase64Pad ? 0 : v[2]) << 6) |
                                   std::uint32_t(v[3] == kBase64Pad ? 0 : v[3]);
        buf_[0] = std::uint8_t(bits >> 16);
        buf_[1] = std::uint8_t(bits >> 8);
        buf_[2] = std::uint8_t(bits);
        bufLen_ = v[2] == kBase64Pad ? 1 : v[3] == kBase64Pad ? 2 : 3;
        bufPos_ = 0;
        return true;
    }

    std::string_view text_;
    std::size_t pos_ = 0;
    std::uint8_t buf_[3] = {};
    int bufLen_ = 0;
    int bufPos_ = 0;
    std::string what_;
};

// ---------------------------------------------------------------- file-wide settings

enum class Compressor { None, ZLib, LZ4, LZMA };

const char* compressorName(Compressor c) {
    switch (c) {
        case Compressor::ZLib: return "zlib";
        case Compressor::LZ4: return "LZ4";
        case Compressor::LZMA: return "LZMA";
        case Compressor::None: break;
    }
    return "uncompressed";
}

struct FileLayout {
    bool swap = false;           // file byte order differs from ours
    std::size_t headerSize = 4;  // UInt32 or UInt64 header words
    Compressor compressor = Compressor::None;
    bool hasAppended = false;
    bool appendedBase64 = false;
    ByteView appended;  // from the byte after '_' to the closing </AppendedData>
};

std::uint64_t readHeaderWord(ByteSource& src, const FileLayout& f) {
    std::uint8_t b[8];
    src.read(b, f.headerSize);
    return f.headerSize == 8 ? loadValue<std::uint64_t>(b, f.swap) : loadValue<std::uint32_t>(b, f.swap);
}

// LZMA (xz) streams reach ratios of several thousand to one (about 6800:1 for
// long runs of zeros with liblzma's encoder); a block claiming more than this
// per compressed byte is corrupt.
constexpr std::uint64_t kLzmaMaxRatio = 1u << 16;
// The decoder's memory cap: VTK's presets (levels 1..9) need at most a 64 MiB dictionary.
constexpr std::uint64_t kLzmaMemLimit = std::uint64_t(1) << 27;

// One .xz stream (as vtkLZMADataCompressor writes it) decoded onto the end of
// `out`, which grows only as data really decodes; it must decode to exactly
// `want` bytes. `error(why)` does not return.
template <class OnError>
void decodeLzmaBlock(const std::vector<std::uint8_t>& comp, std::uint64_t want, std::vector<std::uint8_t>& out,
                     OnError error) {
    lzma_stream s = LZMA_STREAM_INIT;
    struct End {
        lzma_stream* s;
        ~End() { lzma_end(s); }
    } end{&s};
    if (lzma_stream_decoder(&s, kLzmaMemLimit, 0) != LZMA_OK) error("cannot start the LZMA decoder (out of memory)");
    s.next_in = comp.data();
    s.avail_in = comp.size();
    const std::size_t start = out.size();
    std::uint64_t got = 0;
    while (true) {
        // Room for twice what has decoded so far (at least 64 KiB), never more
        // than one byte beyond `want` (that byte catches longer streams).
        if (start + got == out.size()) {
            const std::uint64_t room = std::min<std::uint64_t>(want + 1, std::max<std::uint64_t>(got * 2, 65536));
            out.resize(start + std::size_t(room));
        }
        s.next_out = out.data() + start + got;
        s.avail_out = out.size() - start - std::size_t(got);
        const std::size_t before = s.avail_out;
        const lzma_ret rc = lzma_code(&s, LZMA_FINISH);
        got += before - s.avail_out;
        if (got > want) {
            out.resize(start);
            error("decodes to more than " + str(want) + " bytes");
        }
        if (rc == LZMA_STREAM_END) break;
        if (rc == LZMA_OK) continue;
        out.resize(start);
        switch (rc) {
            case LZMA_MEMLIMIT_ERROR: error("needs more than " + str(kLzmaMemLimit >> 20) + " MiB to decode"); break;
            case LZMA_MEM_ERROR: error("out of memory"); break;
            case LZMA_FORMAT_ERROR: error("not an .xz stream"); break;
            case LZMA_OPTIONS_ERROR: error("unsupported .xz options"); break;
            case LZMA_BUF_ERROR: error("the .xz stream is cut short"); break;
            case LZMA_DATA_ERROR: error("LZMA data error"); break;
            default: error("LZMA decoder error " + str(std::uint64_t(rc))); break;
        }
    }
    out.resize(start + std::size_t(got));
    if (got != want) error("decodes to " + str(got) + " bytes, expected " + str(want));
    if (s.avail_in != 0) error(str(s.avail_in) + " bytes after the end of the .xz stream");
}

// What a piece's points will hold (pieceBytesPerPoint), checked against the
// memory budget once an array's count is known to be backed by its bytes
// (the header's sizes match and fit the data), before its buffer is allocated.
struct PointBudget {
    std::uint64_t points = 0, bytesPerPoint = 0;
    void check() const {
        if (points != 0) io_util::checkPointMemory(points, bytesPerPoint);
    }
};

// The array's data bytes (header consumed, blocks inflated); exactly expectedBytes long.
std::vector<std::uint8_t> readBinaryArray(ByteSource& src, const FileLayout& f, std::size_t expectedBytes,
                                          const std::string& what, const PointBudget& budget) {
    auto mismatch = [&](std::uint64_t has) {
        fail(what + ": count mismatch: data holds " + str(has) + " bytes, NumberOfPoints needs " + str(expectedBytes));
    };
    if (f.compressor == Compressor::None) {
        const std::uint64_t nbytes = readHeaderWord(src, f);
        if (nbytes != expectedBytes) mismatch(nbytes);
        if (nbytes > src.maxBytesLeft())
            fail(what + ": truncated data (header says " + str(nbytes) + " bytes, at most " + str(src.maxBytesLeft()) +
                 " left)");
        budget.check();
        std::vector<std::uint8_t> out(nbytes);
        src.read(out.data(), out.size());
        return out;
    }

    const std::uint64_t nblocks = readHeaderWord(src, f);
    const std::uint64_t blockSize = readHeaderWord(src, f);
    const std::uint64_t lastSize = readHeaderWord(src, f);
    if (nblocks > src.maxBytesLeft() / f.headerSize)
        fail(what + ": compression header corrupt (" + str(nblocks) + " blocks cannot fit in the data)");
    if ((nblocks > 0 && blockSize == 0) || lastSize > blockSize)
        fail(what + ": compression header corrupt (block size " + str(blockSize) + ", last block " + str(lastSize) +
             ")");
    std::vector<std::uint64_t> compSize(nblocks);
    std::uint64_t compTotal = 0;
    for (auto& c : compSize) {
        c = readHeaderWord(src, f);
        if (c > std::numeric_limits<std::uint64_t>::max() - compTotal) fail(what + ": compressed size beyond data");
        compTotal += c;
    }
    std::uint64_t total = 0;
    if (nblocks > 0) {
        if (nblocks - 1 > std::numeric_limits<std::uint64_t>::max() / blockSize)
            fail(what + ": compression header corrupt (size overflows)");
        total = (nblocks - 1) * blockSize;
        const std::uint64_t last = lastSize ? lastSize : blockSize;
        if (total > std::numeric_limits<std::uint64_t>::max() - last)
            fail(what + ": compression header corrupt (size overflows)");
        total += last;
    }
    if (total != expectedBytes) mismatch(total);
    if (compTotal > src.maxBytesLeft())
        fail(what + ": compressed size beyond data (blocks need " + str(compTotal) + " bytes, at most " +
             str(src.maxBytesLeft()) + " left)");

    // No block can inflate beyond its compressor's largest ratio (zlib about
    // 1032:1, LZ4 about 255:1, LZMA a few thousand to one); reject impossible
    // headers before allocating what they claim.
    const char* cname = compressorName(f.compressor);
    const std::uint64_t maxRatio = f.compressor == Compressor::ZLib  ? 1100
                                   : f.compressor == Compressor::LZ4 ? 256
                                                                     : kLzmaMaxRatio;
    auto blockBytes = [&](std::uint64_t k) { return k + 1 == nblocks && lastSize ? lastSize : blockSize; };
    auto blockError = [&](std::uint64_t k, const std::string& why) {
        fail(what + ": " + cname + " block " + str(k + 1) + " of " + str(nblocks) + " corrupt (" + why + ")");
    };
    for (std::uint64_t k = 0; k < nblocks; ++k)
        if (blockBytes(k) / maxRatio > compSize[k] + 1)
            blockError(k, str(compSize[k]) + " compressed bytes cannot hold " + str(blockBytes(k)));

    // LZMA: the output grows as the streams decode (its ratio bound is too loose
    // to allocate on); the others: the whole array at once.
    budget.check();
    std::vector<std::uint8_t> out(f.compressor == Compressor::LZMA ? 0 : total);
    std::vector<std::uint8_t> comp;
    std::uint64_t offset = 0;
    for (std::uint64_t k = 0; k < nblocks; ++k) {
        comp.resize(compSize[k]);
        src.read(comp.data(), comp.size());
        const std::uint64_t want = blockBytes(k);
        if (f.compressor == Compressor::ZLib) {
            uLongf got = uLongf(want);
            const int rc = uncompress(out.data() + offset, &got, comp.data(), uLong(comp.size()));
            if (rc != Z_OK || got != want) {
                const std::string why = rc == Z_OK ? "inflates to " + str(got) + " bytes, expected " + str(want)
                                      : rc == Z_BUF_ERROR ? "inflates to more than " + str(want) + " bytes or is cut short"
                                      : rc == Z_MEM_ERROR ? "out of memory"
                                                          : "zlib data error";
                blockError(k, why);
            }
        } else if (f.compressor == Compressor::LZ4) {
            constexpr std::uint64_t kIntMax = std::uint64_t(std::numeric_limits<int>::max());
            if (comp.size() > kIntMax || want > kIntMax) blockError(k, "block larger than LZ4 allows");
            const int got = LZ4_decompress_safe(reinterpret_cast<const char*>(comp.data()),
                                                reinterpret_cast<char*>(out.data() + offset), int(comp.size()),
                                                int(want));
            if (got < 0) blockError(k, "LZ4 data error, or it decodes to more than " + str(want) + " bytes");
            if (std::uint64_t(got) != want)
                blockError(k, "decodes to " + str(std::uint64_t(got)) + " bytes, expected " + str(want));
        } else {
            decodeLzmaBlock(comp, want, out, [&](const std::string& why) { blockError(k, why); });
        }
        offset += want;
    }
    if (out.size() != total)
        fail(what + ": " + cname + " blocks decode to " + str(out.size()) + " bytes, expected " + str(total));
    return out;
}

// ---------------------------------------------------------------- ascii arrays

template <class T>
bool parseNumber(std::string_view tok, T& v) {
    const char* end = tok.data() + tok.size();
    auto [ptr, ec] = std::from_chars(tok.data(), end, v);
    if (ec == std::errc() && ptr == end) return true;
    if constexpr (std::is_floating_point_v<T>) {
        // Out of range (overflow to inf, or underflow/denormals on some
        // libraries): let strtod decide, as a C parser would.
        if (ec == std::errc::result_out_of_range && ptr == end) {
            const std::string s(tok);
            char* e = nullptr;
            v = std::is_same_v<T, float> ? T(std::strtof(s.c_str(), &e)) : T(std::strtod(s.c_str(), &e));
            return e == s.c_str() + s.size();
        }
    }
    return false;
}

void parseAsciiValues(std::string_view text, std::size_t expected, const ScalarInfo& t, Attribute& out,
                      const std::string& what) {
    const std::size_t reserve = std::min(expected, text.size() / 2 + 1);
    if (out.type == AttributeType::Float)
        out.floats.reserve(reserve);
    else
        out.ints.reserve(reserve);
    std::size_t count = 0;
    std::size_t i = 0;
    while (true) {
        while (i < text.size() && isXmlSpace(text[i])) ++i;
        if (i >= text.size()) break;
        std::size_t j = i;
        while (j < text.size() && !isXmlSpace(text[j])) ++j;
        const std::string_view tok = text.substr(i, j - i);
        i = j;
        if (++count > expected)
            fail(what + ": count mismatch: more than " + str(expected) + " values, NumberOfPoints needs " +
                 str(expected));
        bool ok = false;
        if (t.type == Scalar::Float32) {
            float v = 0;
            ok = parseNumber(tok, v);
            out.floats.push_back(v);
        } else if (t.type == Scalar::Float64) {
            double v = 0;
            ok = parseNumber(tok, v);
            out.floats.push_back(toFloat(v));
        } else {
            std::int64_t v = 0;
            ok = parseNumber(tok, v);
            if (!ok && t.type == Scalar::UInt64) {
                std::uint64_t u = 0;
                ok = parseNumber(tok, u);
                v = std::int64_t(u);
            }
            if (out.type == AttributeType::Float)
                out.floats.push_back(float(v));
            else
                out.ints.push_back(v);
        }
        if (!ok) {
            const std::string shown(tok.substr(0, 40));
            fail(what + ": bad number " + inQuotes(shown) + " in ascii data (value " + str(count) + ")");
        }
    }
    if (count != expected)
        fail(what + ": count mismatch: " + str(count) + " values, NumberOfPoints needs " + str(expected));
}

// ---------------------------------------------------------------- DataArray

// The text content of an element: its direct text children joined (VTK puts
// <InformationKey> children after the data text).
std::string elementText(const tinyxml2::XMLElement* e) {
    std::string s;
    for (const tinyxml2::XMLNode* n = e->FirstChild(); n; n = n->NextSibling())
        if (const auto* t = n->ToText())
            if (t->Value()) s += t->Value();
    return s;
}

std::optional<std::uint64_t> parseCount(const char* s) {
    if (!s) return std::nullopt;
    std::string_view v(s);
    while (!v.empty() && isXmlSpace(v.front())) v.remove_prefix(1);
    while (!v.empty() && isXmlSpace(v.back())) v.remove_suffix(1);
    std::uint64_t out = 0;
    auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
    if (v.empty() || ec != std::errc() || ptr != v.data() + v.size()) return std::nullopt;
    return out;
}

// Reads one DataArray of `tuples` tuples. The result's type is Float for
// float-typed arrays (and always when wantFloat), Int otherwise.
Attribute readDataArray(const tinyxml2::XMLElement* e, std::uint64_t tuples, const FileLayout& f,
                        const std::string& what, bool wantFloat, int requiredComponents = 0,
                        const PointBudget& budget = {}) {
    const char* typeName = e->Attribute("type");
    const ScalarInfo* t = typeName ? findScalar(typeName) : nullptr;
    if (!t) fail(what + ": unsupported type " + inQuotes(typeName ? typeName : "(none)"));

    Attribute a;
    a.type = (t->isFloat || wantFloat) ? AttributeType::Float : AttributeType::Int;
    const char* compText = e->Attribute("NumberOfComponents");
    const auto comps = compText ? parseCount(compText) : std::optional<std::uint64_t>(1);
    if (!comps || *comps == 0 || *comps > 4096)
        fail(what + ": bad NumberOfComponents " + inQuotes(compText ? compText : ""));
    a.components = int(*comps);
    if (requiredComponents && a.components != requiredComponents)
        fail(what + " has " + std::to_string(a.components) + " components, expected " +
             std::to_string(requiredComponents));

    if (tuples > std::numeric_limits<std::uint64_t>::max() / 8 / *comps)
        fail(what + ": count mismatch: NumberOfPoints " + str(tuples) + " is impossibly large");
    const std::uint64_t values = tuples * *comps;
    const std::uint64_t bytes = values * t->size;
    if (bytes > std::numeric_limits<std::size_t>::max())
        fail(what + ": count mismatch: NumberOfPoints " + str(tuples) + " is impossibly large");

    const char* fmtText = e->Attribute("format");
    const std::string_view fmt = fmtText ? fmtText : "";
    if (fmt == "ascii") {
        const std::string text = elementText(e);
        parseAsciiValues(text, std::size_t(values), *t, a, what);
        return a;
    }

    std::vector<std::uint8_t> raw;
    if (fmt == "binary") {
        const std::string text = elementText(e);
        Base64Source src(text, what);
        raw = readBinaryArray(src, f, std::size_t(bytes), what, budget);
    } else if (fmt == "appended") {
        if (!f.hasAppended) fail(what + ": format=\"appended\" but the file has no <AppendedData> section");
        const auto offset = parseCount(e->Attribute("offset"));
        if (!offset) fail(what + ": appended array without a valid offset attribute");
        if (*offset >= f.appended.size())
            fail(what + ": truncated appended data (offset " + str(*offset) + " is beyond its " +
                 str(f.appended.size()) + " bytes)");
        const ByteView at = f.appended.subspan(std::size_t(*offset));
        if (f.appendedBase64) {
            Base64Source src(std::string_view(reinterpret_cast<const char*>(at.data()), at.size()), what);
            raw = readBinaryArray(src, f, std::size_t(bytes), what, budget);
        } else {
            RawSource src(at, what);
            raw = readBinaryArray(src, f, std::size_t(bytes), what, budget);
        }
    } else {
        fail(what + ": unsupported format " + inQuotes(fmt) + " (expected ascii, binary or appended)");
    }
    convertValues(raw.data(), std::size_t(values), *t, f.swap && t->size > 1, a);
    return a;
}

// ---------------------------------------------------------------- attribute names

// The point arrays of one piece, named as the ParticleSet will hold them.
// Bytes per point the reader holds at a piece's peak: the positions (12)
// and the Points array they are copied from (3 floats, 12), each point
// array's values as an Attribute (a float component 4, an integer one 8),
// and the largest array's decoded bytes once more (readDataArray's buffer
// before it becomes values). Arrays readPointData would skip count too.
std::uint64_t pieceBytesPerPoint(const tinyxml2::XMLElement* piece) {
    std::uint64_t held = 2 * sizeof(glm::vec3), largestRaw = 0;
    auto add = [&](const tinyxml2::XMLElement* e, bool asFloat) {
        const char* typeName = e->Attribute("type");
        const ScalarInfo* t = typeName ? findScalar(typeName) : nullptr;
        const char* compText = e->Attribute("NumberOfComponents");
        const auto comps = compText ? parseCount(compText) : std::optional<std::uint64_t>(1);
        if (!t || !comps || *comps == 0 || *comps > 4096) return;  // readDataArray refuses it
        if (!asFloat) held += *comps * (t->isFloat ? sizeof(float) : sizeof(std::int64_t));
        largestRaw = std::max<std::uint64_t>(largestRaw, *comps * t->size);
    };
    if (const auto* points = piece->FirstChildElement("Points"))
        if (const auto* e = points->FirstChildElement("DataArray")) add(e, true);
    if (const auto* pd = piece->FirstChildElement("PointData"))
        for (const auto* e = pd->FirstChildElement("DataArray"); e; e = e->NextSiblingElement("DataArray")) add(e, false);
    return held + largestRaw;
}

std::vector<Attribute> readPointData(const tinyxml2::XMLElement* piece, std::uint64_t tuples, const FileLayout& f,
                                     const std::string& where, std::vector<std::string>& warnings,
                                     const PointBudget& budget) {
    std::vector<Attribute> attrs;
    const tinyxml2::XMLElement* pd = piece->FirstChildElement("PointData");
    if (!pd) return attrs;
    int index = 0;
    for (const auto* e = pd->FirstChildElement("DataArray"); e; e = e->NextSiblingElement("DataArray"), ++index) {
        const char* nameAttr = e->Attribute("Name");
        const std::string original = nameAttr && *nameAttr ? nameAttr : "array" + std::to_string(index);
        const std::string what = "point array " + inQuotes(original) + where;
        const char* typeName = e->Attribute("type");
        if (!typeName || !findScalar(typeName)) {
            warnings.push_back("skipped " + what + " of unsupported type " + inQuotes(typeName ? typeName : "(none)"));
            continue;
        }
        Attribute a = readDataArray(e, tuples, f, what, false, 0, budget);
        // The alias table every reader shares (io/attribute_names.h): Vel,
        // Rhop, Idp (DualSPHysics), Velocity, rho, ID, ... (any case).
        std::string name(io_util::canonicalArrayName(original, a.components));
        if (name.empty()) name = original;
        if (name == kAttrId && !io_util::floatIdsToInt(a)) name = original;
        if ((name == kAttrVelocity || name == kAttrDensity) && a.type != AttributeType::Float) name = original;
        const auto taken = [&](const std::string& n) {
            return std::any_of(attrs.begin(), attrs.end(), [&](const Attribute& x) { return x.name == n; });
        };
        if (taken(name)) name = original;
        if (taken(name)) {
            warnings.push_back("skipped duplicate " + what);
            continue;
        }
        a.name = std::move(name);
        attrs.push_back(std::move(a));
    }
    return attrs;
}

// ---------------------------------------------------------------- XML before the appended data

// Closing tags for the elements still open at the end of `xml`, innermost first.
std::string closeOpenElements(std::string_view xml) {
    std::vector<std::string_view> open;
    std::size_t i = 0;
    while ((i = xml.find('<', i)) != std::string_view::npos) {
        auto skipPast = [&](std::string_view end) {
            const std::size_t k = xml.find(end, i);
            i = k == std::string_view::npos ? xml.size() : k + end.size();
        };
        if (xml.substr(i, 4) == "<!--") {
            skipPast("-->");
            continue;
        }
        if (xml.substr(i, 9) == "<![CDATA[") {
            skipPast("]]>");
            continue;
        }
        if (i + 1 < xml.size() && (xml[i + 1] == '?' || xml[i + 1] == '!')) {
            skipPast(">");
            continue;
        }
        const bool closing = i + 1 < xml.size() && xml[i + 1] == '/';
        const std::size_t nameStart = i + (closing ? 2 : 1);
        std::size_t nameEnd = nameStart;
        while (nameEnd < xml.size() && !isXmlSpace(xml[nameEnd]) && xml[nameEnd] != '>' && xml[nameEnd] != '/')
            ++nameEnd;
        std::size_t j = nameEnd;
        char quote = 0;
        for (; j < xml.size(); ++j) {
            const char c = xml[j];
            if (quote) {
                if (c == quote) quote = 0;
            } else if (c == '"' || c == '\'') {
                quote = c;
            } else if (c == '>') {
                break;
            }
        }
        if (j >= xml.size()) break;  // unterminated tag: the XML parser reports it
        const std::string_view name = xml.substr(nameStart, nameEnd - nameStart);
        if (closing) {
            if (!open.empty() && open.back() == name) open.pop_back();
        } else if (xml[j - 1] != '/') {
            open.push_back(name);
        }
        i = j + 1;
    }
    std::string out;
    for (auto it = open.rbegin(); it != open.rend(); ++it) out += "</" + std::string(*it) + ">";
    return out;
}

std::size_t findBytes(ByteView data, std::string_view needle, std::size_t from = 0) {
    if (needle.size() > data.size()) return std::string_view::npos;
    const auto it = std::search(data.begin() + std::ptrdiff_t(std::min(from, data.size())), data.end(),
                                needle.begin(), needle.end(),
                                [](std::uint8_t a, char b) { return a == std::uint8_t(b); });
    return it == data.end() ? std::string_view::npos : std::size_t(it - data.begin());
}

std::size_t rfindBytes(ByteView data, std::string_view needle) {
    const std::string_view s(reinterpret_cast<const char*>(data.data()), data.size());
    return s.rfind(needle);
}

// Splits the file into the XML the parser gets and the appended data section.
std::string prepareXml(ByteView data, FileLayout& f) {
    const std::size_t tag = findBytes(data, "<AppendedData");
    if (tag == std::string_view::npos) return std::string(data.begin(), data.end());

    const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
    const std::size_t tagEnd = text.find('>', tag);
    if (tagEnd == std::string_view::npos) fail("truncated: the <AppendedData> tag is not closed");
    const std::string_view tagText = text.substr(tag, tagEnd + 1 - tag);

    // The tag's own attributes, parsed as an empty element.
    const bool selfClosing = tagText.size() >= 2 && tagText[tagText.size() - 2] == '/';
    std::string tagXml(tagText.substr(0, tagText.size() - (selfClosing ? 2 : 1)));
    tagXml += "/>";
    tinyxml2::XMLDocument tagDoc;
    if (tagDoc.Parse(tagXml.c_str(), tagXml.size()) != tinyxml2::XML_SUCCESS || !tagDoc.RootElement())
        fail("malformed <AppendedData> tag");
    const char* enc = tagDoc.RootElement()->Attribute("encoding");
    const std::string_view encoding = enc ? enc : "raw";
    if (encoding == "base64")
        f.appendedBase64 = true;
    else if (encoding != "raw")
        fail("unsupported AppendedData encoding " + inQuotes(encoding) + " (expected raw or base64)");

    if (selfClosing) {
        f.hasAppended = true;  // <AppendedData/>: present but empty
        f.appended = {};
    } else {
        std::size_t p = tagEnd + 1;
        while (p < text.size() && isXmlSpace(text[p])) ++p;
        if (p >= text.size()) fail("truncated appended data (file ends before the '_' marker)");
        if (text[p] != '_') fail("AppendedData does not start with the '_' marker");
        const std::size_t start = p + 1;
        const std::size_t close = rfindBytes(data, "</AppendedData>");
        if (close == std::string_view::npos || close < start)
            fail("truncated appended data (the file ends before </AppendedData>)");
        std::size_t after = close + std::string_view("</AppendedData>").size();
        while (after < text.size() && isXmlSpace(text[after])) ++after;
        if (text.substr(after, 10) != "</VTKFile>")
            fail("truncated: </VTKFile> missing after the appended data");
        f.hasAppended = true;
        f.appended = data.subspan(start, close - start);
    }

    std::string xml(text.substr(0, tag));
    xml += closeOpenElements(xml);
    return xml;
}

// ---------------------------------------------------------------- the whole file

ParticleSet parseDocument(ByteView data) {
    if (data.empty()) fail("file is empty");
    FileLayout f;
    const std::string xml = prepareXml(data, f);

    tinyxml2::XMLDocument doc;
    if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
        const std::string err = doc.ErrorStr() ? doc.ErrorStr() : "unknown error";
        if (xml.find("<VTKFile") == std::string::npos) fail("not a VTKFile (not VTK XML: " + err + ")");
        fail("malformed or truncated XML: " + err);
    }
    const tinyxml2::XMLElement* root = doc.RootElement();
    if (!root) fail("not a VTKFile (no XML element)");
    if (std::string_view(root->Name()) != "VTKFile")
        fail("not a VTKFile (root element is <" + std::string(root->Name()) + ">)");

    const char* typeAttr = root->Attribute("type");
    const std::string_view type = typeAttr ? typeAttr : "";
    if (type != "UnstructuredGrid" && type != "PolyData")
        fail("unsupported VTK XML dataset type " + inQuotes(type) + " (expected UnstructuredGrid or PolyData)");

    const char* order = root->Attribute("byte_order");
    if (order && std::string_view(order) != "LittleEndian" && std::string_view(order) != "BigEndian")
        fail("unsupported byte_order " + inQuotes(order));
    const bool fileBig = order && std::string_view(order) == "BigEndian";
    f.swap = fileBig != (std::endian::native == std::endian::big);

    if (const char* h = root->Attribute("header_type")) {
        if (std::string_view(h) == "UInt64")
            f.headerSize = 8;
        else if (std::string_view(h) != "UInt32")
            fail("unsupported header_type " + inQuotes(h) + " (expected UInt32 or UInt64)");
    }
    if (const char* c = root->Attribute("compressor"); c && *c) {
        const std::string_view name(c);
        if (name == "vtkZLibDataCompressor")
            f.compressor = Compressor::ZLib;
        else if (name == "vtkLZ4DataCompressor")
            f.compressor = Compressor::LZ4;
        else if (name == "vtkLZMADataCompressor")
            f.compressor = Compressor::LZMA;
        else
            fail("unsupported compressor " + inQuotes(c) +
                 " (expected vtkZLibDataCompressor, vtkLZ4DataCompressor or vtkLZMADataCompressor)");
    }

    const tinyxml2::XMLElement* dataset = root->FirstChildElement(std::string(type).c_str());
    if (!dataset) fail("missing <" + std::string(type) + "> element");
    const tinyxml2::XMLElement* firstPiece = dataset->FirstChildElement("Piece");
    if (!firstPiece) fail("no <Piece> in <" + std::string(type) + ">");
    const bool severalPieces = firstPiece->NextSiblingElement("Piece") != nullptr;

    ParticleSet set;
    int pieceIndex = 0;
    for (const auto* piece = firstPiece; piece; piece = piece->NextSiblingElement("Piece"), ++pieceIndex) {
        const std::string where = severalPieces ? " (piece " + std::to_string(pieceIndex + 1) + ")" : "";
        const char* npText = piece->Attribute("NumberOfPoints");
        const auto np = parseCount(npText);
        if (!np) fail("missing or bad NumberOfPoints " + inQuotes(npText ? npText : "") + where);
        const PointBudget budget{set.positions.size() + std::min<std::uint64_t>(*np, std::uint64_t(1) << 62),
                                 pieceBytesPerPoint(piece)};

        // Points.
        Attribute positions;
        const tinyxml2::XMLElement* points = piece->FirstChildElement("Points");
        const tinyxml2::XMLElement* pointsArray = points ? points->FirstChildElement("DataArray") : nullptr;
        if (!pointsArray) {
            if (*np > 0) fail("missing Points" + where);
        } else {
            positions = readDataArray(pointsArray, *np, f, "Points" + where, true, 3, budget);
        }
        std::vector<Attribute> attrs = readPointData(piece, *np, f, where, set.warnings, budget);

        // Append this piece.
        if (set.positions.size() + *np > std::numeric_limits<std::size_t>::max() / sizeof(glm::vec3))
            fail("count mismatch: too many points");
        const std::size_t before = set.positions.size();
        set.positions.reserve(before + std::size_t(*np));
        for (std::size_t i = 0; i < *np; ++i)
            set.positions.emplace_back(positions.floats[3 * i], positions.floats[3 * i + 1],
                                       positions.floats[3 * i + 2]);
        if (pieceIndex == 0) {
            set.attributes = std::move(attrs);
            continue;
        }
        // Later pieces: keep only attributes every piece has, alike.
        for (auto it = set.attributes.begin(); it != set.attributes.end();) {
            auto match = std::find_if(attrs.begin(), attrs.end(), [&](const Attribute& a) {
                return a.name == it->name && a.type == it->type && a.components == it->components;
            });
            if (match == attrs.end()) {
                set.warnings.push_back("dropped point array " + inQuotes(it->name) + ": missing or different" + where);
                it = set.attributes.erase(it);
                continue;
            }
            it->floats.insert(it->floats.end(), match->floats.begin(), match->floats.end());
            it->ints.insert(it->ints.end(), match->ints.begin(), match->ints.end());
            attrs.erase(match);
            ++it;
        }
        for (const auto& extra : attrs)
            set.warnings.push_back("ignored point array " + inQuotes(extra.name) + where + ": not in the first piece");
    }
    return set;
}

}  // namespace

Result<ParticleSet> parseVtu(ByteView data, const std::string& name) {
    return io_util::guardParse(name, "VTK XML", [&] { return parseDocument(data); });
}

}  // namespace meniscus
