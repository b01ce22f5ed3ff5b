// Buffered binary output for the particle writers: values in a stated byte
// order into a 1 MiB buffer, flushed to a file, plain or gzip-compressed, so
// a frame of any size is written in bounded memory. Internal to src/io.
// Failures (disk full, a closed pipe) throw std::runtime_error, which
// writeAtomically (atomic_file.h) turns into an Error naming the file after
// removing the temporary file: a failed write leaves nothing behind.
#pragma once

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace meniscus::io_write {

class ByteOut {
public:
    // Opens `path` for writing (truncating it); gzip-compressed at `gzipLevel`
    // (zlib's 1 to 9) when it is above 0.
    ByteOut(const std::filesystem::path& path, int gzipLevel);
    ~ByteOut();
    ByteOut(const ByteOut&) = delete;
    ByteOut& operator=(const ByteOut&) = delete;

    void bytes(const void* p, std::size_t n) {
        if (n > kBufferBytes - buf_.size()) drain();
        if (n > kBufferBytes) return sink(static_cast<const std::uint8_t*>(p), n);
        const auto* b = static_cast<const std::uint8_t*>(p);
        buf_.insert(buf_.end(), b, b + n);
    }
    void text(std::string_view s) { bytes(s.data(), s.size()); }
    void u8(std::uint8_t v) { bytes(&v, 1); }

    // Unsigned words and floats in big- (BE) or little-endian (LE) order.
    template <class T>
    void be(T v) { put(v, std::endian::big); }
    template <class T>
    void le(T v) { put(v, std::endian::little); }
    template <class T>
    void put(T v, std::endian order) {
        static_assert(std::is_trivially_copyable_v<T> && (sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4 ||
                                                          sizeof(T) == 8));
        std::uint8_t b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        if (order != std::endian::native)
            for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
        bytes(b, sizeof(T));
    }

    // Flushes everything (and ends the gzip stream); throws on failure.
    // Must be called once, last: the destructor only closes the file.
    void finish();

private:
    static constexpr std::size_t kBufferBytes = std::size_t(1) << 20;

    void drain();
    void sink(const std::uint8_t* p, std::size_t n);  // to the file, compressing if asked
    void fileWrite(const std::uint8_t* p, std::size_t n);

    struct Deflater;
    std::FILE* fp_ = nullptr;
    std::unique_ptr<Deflater> z_;
    std::vector<std::uint8_t> buf_;
    std::filesystem::path path_;
};

}  // namespace meniscus::io_write
