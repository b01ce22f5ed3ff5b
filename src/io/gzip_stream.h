// Piecewise gzip/zlib inflation, so a reader can take exactly the bytes its
// header says it needs (and check they exist) without holding the whole
// inflated stream: a decompression bomb costs time bounded by the header's
// legitimate need, never memory.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// The most deflate can expand: a 258-byte match coded in 2 bits is 1032:1
// (RFC 1951). No honest header can claim more inflated bytes than this times
// the compressed size.
inline constexpr std::uint64_t kMaxDeflateRatio = 1032;

class InflateStream {
public:
    // `data` must outlive the stream; `name` is used in error messages.
    InflateStream(ByteView data, std::string name);
    ~InflateStream();
    InflateStream(const InflateStream&) = delete;
    InflateStream& operator=(const InflateStream&) = delete;

    // Inflates up to n bytes into dst; fewer only at the end of the data
    // (concatenated gzip members are inflated one after another, as gunzip
    // does; anything else after a member is ignored). Errors name the file:
    // corrupt data, a truncated stream.
    Result<std::size_t> read(std::uint8_t* dst, std::size_t n);
    // The same, discarding the bytes: how many there were (fewer than n only
    // at the end of the data).
    Result<std::uint64_t> skip(std::uint64_t n);
    // True once the last member has ended.
    bool ended() const { return ended_; }

private:
    struct Z;
    std::unique_ptr<Z> z_;
    ByteView data_;
    std::string name_;
    std::size_t inPos_ = 0;
    bool ended_ = false;
};

}  // namespace meniscus
