// gzip / zlib stream inflation into memory (RFC 1952 gzip, RFC 1950 zlib; the
// header kind is auto-detected by zlib's inflateInit2 with windowBits 15+32).
// Concatenated gzip members are inflated one after another, as gunzip does.
// Output is capped so that garbage or a decompression bomb cannot exhaust memory.
#include <zlib.h>

#include <algorithm>
#include <climits>
#include <new>

#include "meniscus/io.h"

namespace meniscus {

namespace {

constexpr std::uint64_t kMaxInflatedBytes = std::uint64_t(4) << 30;  // 4 GiB

// Owns a z_stream and ends it on every exit path.
struct Inflater {
    z_stream zs{};
    bool initialised = false;
    ~Inflater() {
        if (initialised) inflateEnd(&zs);
    }
};

bool startsGzipMember(ByteView data, std::size_t at) {
    return data.size() >= at + 2 && data[at] == 0x1f && data[at + 1] == 0x8b;
}

}  // namespace

Result<std::vector<std::uint8_t>> inflateGzip(ByteView data, const std::string& name) {
    try {
        if (data.empty()) return makeError(name, "gzip stream is truncated (no data)");
        Inflater inf;
        if (inflateInit2(&inf.zs, 15 + 32) != Z_OK) return makeError(name, "cannot initialise zlib");
        inf.initialised = true;

        std::vector<std::uint8_t> out;
        // The input size is a safe first guess; a gzip trailer's ISIZE is not
        // trusted because garbage could claim gigabytes.
        out.resize(std::max<std::size_t>(data.size() * 4, 64 * 1024));

        std::size_t inPos = 0;   // bytes of `data` consumed
        std::size_t outPos = 0;  // bytes of `out` filled
        for (;;) {
            if (outPos == out.size()) {
                if (out.size() >= kMaxInflatedBytes)
                    return makeError(name, "gzip data inflates to more than 4 GiB; refusing to read it");
                out.resize(std::size_t(std::min<std::uint64_t>(std::uint64_t(out.size()) * 2, kMaxInflatedBytes)));
            }
            const std::size_t inChunk = std::min<std::size_t>(data.size() - inPos, UINT_MAX);
            const std::size_t outChunk = std::min<std::size_t>(out.size() - outPos, UINT_MAX);
            inf.zs.next_in = const_cast<Bytef*>(data.data() + inPos);
            inf.zs.avail_in = uInt(inChunk);
            inf.zs.next_out = out.data() + outPos;
            inf.zs.avail_out = uInt(outChunk);

            const int rc = inflate(&inf.zs, Z_NO_FLUSH);
            inPos += inChunk - inf.zs.avail_in;
            outPos += outChunk - inf.zs.avail_out;

            if (rc == Z_STREAM_END) {
                // Another gzip member may follow (concatenated .gz files); anything
                // else after the end of the stream is ignored.
                if (!startsGzipMember(data, inPos)) break;
                if (inflateReset(&inf.zs) != Z_OK) return makeError(name, "cannot reset zlib");
                continue;
            }
            if (rc == Z_DATA_ERROR || rc == Z_NEED_DICT || rc == Z_STREAM_ERROR) {
                const char* msg = inf.zs.msg ? inf.zs.msg : "invalid data";
                return makeError(name, std::string("gzip data is corrupt: ") + msg);
            }
            if (rc == Z_MEM_ERROR) return makeError(name, "out of memory while inflating gzip data");
            // Z_OK or Z_BUF_ERROR: progress is possible only with more input or output.
            if (inPos == data.size() && inf.zs.avail_out != 0) return makeError(name, "gzip stream is truncated");
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
