// gzip / zlib stream inflation (RFC 1952 gzip, RFC 1950 zlib; the header kind
// is auto-detected by zlib's inflateInit2 with windowBits 15+32), piece by
// piece (InflateStream, gzip_stream.h) or whole into memory (inflateGzip).
// Whole inflation is capped so that garbage or a decompression bomb cannot
// exhaust memory.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <climits>
#include <new>

#include "io/gzip_stream.h"
#include "meniscus/io.h"

namespace meniscus {

namespace {

constexpr std::uint64_t kMaxInflatedBytes = std::uint64_t(4) << 30;  // 4 GiB

bool startsGzipMember(ByteView data, std::size_t at) {
    return data.size() >= at + 2 && data[at] == 0x1f && data[at + 1] == 0x8b;
}

}  // namespace

struct InflateStream::Z {
    z_stream zs{};
    bool initialised = false;
    ~Z() {
        if (initialised) inflateEnd(&zs);
    }
};

InflateStream::InflateStream(ByteView data, std::string name)
    : z_(std::make_unique<Z>()), data_(data), name_(std::move(name)) {}

InflateStream::~InflateStream() = default;

Result<std::size_t> InflateStream::read(std::uint8_t* dst, std::size_t n) {
    if (!z_->initialised) {
        if (data_.empty()) return makeError(name_, "gzip stream is truncated (no data)");
        if (inflateInit2(&z_->zs, 15 + 32) != Z_OK) return makeError(name_, "cannot initialise zlib");
        z_->initialised = true;
    }
    z_stream& zs = z_->zs;
    std::size_t got = 0;
    while (got < n && !ended_) {
        const std::size_t inChunk = std::min<std::size_t>(data_.size() - inPos_, UINT_MAX);
        const std::size_t outChunk = std::min<std::size_t>(n - got, UINT_MAX);
        zs.next_in = const_cast<Bytef*>(data_.data() + inPos_);
        zs.avail_in = uInt(inChunk);
        zs.next_out = dst + got;
        zs.avail_out = uInt(outChunk);

        const int rc = inflate(&zs, Z_NO_FLUSH);
        inPos_ += inChunk - zs.avail_in;
        got += outChunk - zs.avail_out;

        if (rc == Z_STREAM_END) {
            // Another gzip member may follow (concatenated .gz files); anything
            // else after the end of the stream is ignored.
            if (!startsGzipMember(data_, inPos_)) {
                ended_ = true;
                break;
            }
            if (inflateReset(&zs) != Z_OK) return makeError(name_, "cannot reset zlib");
            continue;
        }
        if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT || rc == Z_STREAM_ERROR) {
            const char* msg = zs.msg ? zs.msg : "invalid data";
            return makeError(name_, std::string("gzip data is corrupt: ") + msg);
        }
        if (rc == Z_MEM_ERROR) return makeError(name_, "out of memory while inflating gzip data");
        // Z_OK or Z_BUF_ERROR: progress is possible only with more input or output.
        if (inPos_ == data_.size() && zs.avail_out != 0) return makeError(name_, "gzip stream is truncated");
    }
    return got;
}

Result<std::uint64_t> InflateStream::skip(std::uint64_t n) {
    std::array<std::uint8_t, 1 << 16> scratch;
    std::uint64_t done = 0;
    while (done < n && !ended_) {
        auto got = read(scratch.data(), std::size_t(std::min<std::uint64_t>(n - done, scratch.size())));
        if (!got) return got.error();
        done += *got;
    }
    return done;
}

Result<std::vector<std::uint8_t>> inflateGzip(ByteView data, const std::string& name) {
    try {
        InflateStream in(data, name);
        std::vector<std::uint8_t> out;
        // The input size is a safe first guess; a gzip trailer's ISIZE is not
        // trusted because garbage could claim gigabytes.
        out.resize(std::max<std::size_t>(data.size() * 4, 64 * 1024));
        std::size_t outPos = 0;  // bytes of `out` filled
        for (;;) {
            auto got = in.read(out.data() + outPos, out.size() - outPos);
            if (!got) return got.error();
            outPos += *got;
            if (in.ended()) break;
            if (out.size() >= kMaxInflatedBytes)
                return makeError(name, "gzip data inflates to more than 4 GiB; refusing to read it");
            out.resize(std::size_t(std::min<std::uint64_t>(std::uint64_t(out.size()) * 2, kMaxInflatedBytes)));
        }
        out.resize(outPos);
        out.shrink_to_fit();
        return out;
    } catch (const std::bad_alloc&) {
        return makeError(name, "out of memory while inflating gzip data");
    } catch (const std::exception& e) {
        return makeError(name, std::string("gzip inflation failed: ") + e.what());
    }
}

}  // namespace meniscus
