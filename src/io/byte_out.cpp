// Buffered file output, optionally through a gzip stream (see byte_out.h).
#include "io/byte_out.h"

#include <algorithm>
#include <cerrno>
#include <stdexcept>
#include <string>

#include <zlib.h>

namespace meniscus::io_write {

// A zlib deflate stream with a gzip wrapper (RFC 1952; windowBits 15 + 16).
// Its header carries no name and mtime 0, so the same particles always give
// the same bytes.
struct ByteOut::Deflater {
    z_stream z{};
    std::vector<std::uint8_t> out = std::vector<std::uint8_t>(std::size_t(256) << 10);
    bool open = false;
    ~Deflater() {
        if (open) deflateEnd(&z);
    }
};

namespace {
[[noreturn]] void failed(const std::string& what) { throw std::runtime_error(what); }
}  // namespace

ByteOut::ByteOut(const std::filesystem::path& path, int gzipLevel) : path_(path) {
    fp_ = std::fopen(path.c_str(), "wb");
    if (!fp_) failed(std::string("cannot open for writing: ") + std::strerror(errno));
    buf_.reserve(kBufferBytes);
    if (gzipLevel > 0) {
        z_ = std::make_unique<Deflater>();
        if (deflateInit2(&z_->z, gzipLevel, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
            failed("cannot start gzip compression");
        z_->open = true;
    }
}

ByteOut::~ByteOut() {
    if (fp_) std::fclose(fp_);
}

void ByteOut::fileWrite(const std::uint8_t* p, std::size_t n) {
    if (n > 0 && std::fwrite(p, 1, n, fp_) != n) failed(std::strerror(errno));
}

void ByteOut::sink(const std::uint8_t* p, std::size_t n) {
    if (!z_) return fileWrite(p, n);
    z_stream& z = z_->z;
    while (n > 0) {
        // avail_in is 32 bits: feed at most 1 GiB at a time.
        const std::size_t take = std::min<std::size_t>(n, std::size_t(1) << 30);
        z.next_in = const_cast<Bytef*>(p);
        z.avail_in = uInt(take);
        do {
            z.next_out = z_->out.data();
            z.avail_out = uInt(z_->out.size());
            if (deflate(&z, Z_NO_FLUSH) == Z_STREAM_ERROR) failed("gzip compression failed");
            fileWrite(z_->out.data(), z_->out.size() - z.avail_out);
        } while (z.avail_out == 0);
        p += take;
        n -= take;
    }
}

void ByteOut::drain() {
    sink(buf_.data(), buf_.size());
    buf_.clear();
}

void ByteOut::finish() {
    drain();
    if (z_) {
        z_stream& z = z_->z;
        z.next_in = nullptr;
        z.avail_in = 0;
        int rc = Z_OK;
        do {
            z.next_out = z_->out.data();
            z.avail_out = uInt(z_->out.size());
            rc = deflate(&z, Z_FINISH);
            if (rc == Z_STREAM_ERROR) failed("gzip compression failed");
            fileWrite(z_->out.data(), z_->out.size() - z.avail_out);
        } while (rc != Z_STREAM_END);
    }
    std::FILE* fp = fp_;
    fp_ = nullptr;
    const bool flushed = std::fflush(fp) == 0 && !std::ferror(fp);
    const int err = errno;
    if (std::fclose(fp) != 0 || !flushed)
        failed(std::strerror(flushed ? errno : err));
}

}  // namespace meniscus::io_write
