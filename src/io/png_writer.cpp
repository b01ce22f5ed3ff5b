// writePng: an 8-bit RGBA (or RGB) PNG from a linear float image.
//
// - Row order: Image row 0 is the top row, and PNG rows are stored top first,
//   so row y of the image is PNG row y (no flip).
// - Colour: R, G, B are encoded from linear with the exact piecewise sRGB
//   transfer function (src/shared/srgb.h, which the viewer's present shader
//   uses too), clamped to [0,1] and rounded to the nearest 8-bit value;
//   the file carries an sRGB chunk (plus the matching gAMA/cHRM) so viewers
//   know it. Alpha is coverage and stays linear (clamped, rounded). NaN -> 0.
// - An 8-bit image already encoded (a window's framebuffer) is written as is.
// - Written through writeAtomically: a failed write leaves no file behind.
// - libpng reports errors with longjmp, so every libpng call lives in
//   writePngRows(), a function with no C++ objects that have destructors.
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <png.h>

#include "atomic_file.h"
#include "meniscus/io.h"
#include "shared/srgb.h"

namespace meniscus {
namespace {

// Exact sRGB encoding of one linear value to 8 bits.
png_byte encodeSrgb(float linear) { return png_byte(std::lround(shared::srgbEncode(linear) * 255.0)); }

// encodeSrgb by table, the same bytes a few times faster (a frame's 8-bit
// colour, for a PNG or a movie, was three pow() calls a pixel). Rounded to 8
// bits the curve is a non-decreasing step function of the linear value with
// 255 steps; step k (the smallest float that encodes to k + 1) is found once
// by bisection over the floats of [0, 1] on encodeSrgb itself. A value in
// (0, 1) then looks up the level at the start of its bucket (its top 16 bits:
// 2^-7 of its size), which holds at most one step (the curve rises at most
// 255 x 1.055 / 2.4 x 2^-7 < 0.9 levels across a bucket; checked here, the
// direct formula answering otherwise), and adds one past that bucket's step.
// io_writers_test compares it with encodeSrgb around every step.
class SrgbTable {
public:
    SrgbTable() {
        const std::uint32_t one = bitsOf(1.0f);
        for (int k = 0; k < 255; ++k) {
            std::uint32_t lo = 0, hi = one;  // encodeSrgb(lo) <= k < encodeSrgb(hi)
            while (hi - lo > 1) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                (encodeSrgb(floatOf(mid)) > k ? hi : lo) = mid;
            }
            step_[std::size_t(k)] = floatOf(hi);
        }
        step_[255] = std::numeric_limits<float>::infinity();
        base_.resize((one >> 16) + 1);
        for (std::uint32_t b = 0; b < base_.size(); ++b) base_[b] = encodeSrgb(floatOf(b << 16));
        for (int k = 0; k + 1 < 255; ++k)
            if (bitsOf(step_[std::size_t(k)]) >> 16 == bitsOf(step_[std::size_t(k) + 1]) >> 16) exact_ = false;
    }
    png_byte operator()(float linear) const {
        if (!(linear > 0.0f)) return 0;  // also NaN, as encodeSrgb
        if (linear >= 1.0f || !exact_) return encodeSrgb(linear);
        const png_byte level = base_[bitsOf(linear) >> 16];
        return png_byte(level + (linear >= step_[level] ? 1 : 0));
    }

private:
    static std::uint32_t bitsOf(float f) { return std::bit_cast<std::uint32_t>(f); }
    static float floatOf(std::uint32_t b) { return std::bit_cast<float>(b); }
    std::array<float, 256> step_{};
    std::vector<png_byte> base_;
    bool exact_ = true;
};

const SrgbTable& srgbTable() {
    static const SrgbTable table;
    return table;
}

// Linear (alpha) value to 8 bits.
png_byte encodeLinear(float value) {
    double x = value;
    if (!(x > 0.0)) x = 0.0;  // also NaN -> 0
    if (x > 1.0) x = 1.0;
    return png_byte(std::lround(x * 255.0));
}

struct PngErrorState {
    char message[256];
    char warning[256];  // the last warning, often the detail behind an error
    int writeErrno;     // the system's reason a write failed (ENOSPC, EFBIG, EIO), 0 when none
};

void onPngError(png_structp png, png_const_charp msg) {
    auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
    std::snprintf(state->message, sizeof state->message, "%s", msg ? msg : "libpng error");
    png_longjmp(png, 1);
}

void onPngWarning(png_structp png, png_const_charp msg) {
    auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
    std::snprintf(state->warning, sizeof state->warning, "%s", msg ? msg : "");
}

// libpng's own writer says only "Write Error" when fwrite fails; this one
// keeps the system's reason (a full disk: "No space left on device").
void onPngWrite(png_structp png, png_bytep data, std::size_t size) {
    auto* fp = static_cast<std::FILE*>(png_get_io_ptr(png));
    if (std::fwrite(data, 1, size, fp) != size) {
        auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
        state->writeErrno = errno ? errno : EIO;
        png_error(png, "write failed");
    }
}
void onPngFlush(png_structp png) { std::fflush(static_cast<std::FILE*>(png_get_io_ptr(png))); }

// All libpng calls. No objects with non-trivial destructors live in this
// frame, so the longjmp out of onPngError is safe. Returns false on error with
// the reason in err->message.
bool writePngRows(std::FILE* fp, int width, int height, int channels, const png_byte* data,
                  PngErrorState* err) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, err, onPngError, onPngWarning);
    if (!png) {
        std::snprintf(err->message, sizeof err->message, "cannot initialise libpng");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        std::snprintf(err->message, sizeof err->message, "cannot initialise libpng");
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, fp, onPngWrite, onPngFlush);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8,
                 channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    const std::size_t stride = std::size_t(width) * std::size_t(channels);
    for (int y = 0; y < height; ++y) png_write_row(png, data + std::size_t(y) * stride);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

// Writes rows already encoded to 8 bits (`channels` bytes a pixel, top row
// first) to a temporary name and renames it.
Status writeEncoded(const std::filesystem::path& path, int width, int height, int channels,
                    const std::vector<png_byte>& bytes) {
    const std::string name = path.string();
    return writeAtomically(path, [&](const std::filesystem::path& tmp) -> Status {
        std::FILE* fp = std::fopen(tmp.c_str(), "wb");
        if (!fp) return makeError(name, std::string("cannot open for writing: ") + std::strerror(errno));
        PngErrorState err{};
        const bool ok = writePngRows(fp, width, height, channels, bytes.data(), &err);
        const bool flushed = std::fflush(fp) == 0 && !std::ferror(fp);
        const int flushErrno = errno;
        const bool closed = std::fclose(fp) == 0;
        if (!ok && err.writeErrno) return makeError(name, std::string("write failed: ") + std::strerror(err.writeErrno));
        if (!ok) {
            std::string why = std::string("PNG write failed: ") + err.message;
            if (err.warning[0]) why += std::string(" (") + err.warning + ")";
            return makeError(name, why);
        }
        if (!flushed || !closed)
            return makeError(name, std::string("write failed: ") + std::strerror(flushed ? errno : flushErrno));
        return okStatus();
    });
}

// An empty image or one whose pixel count does not match its size is an error.
template <class T>
Status checkShape(const std::filesystem::path& path, const Image<T>& image) {
    const std::string name = path.string();
    if (image.width <= 0 || image.height <= 0 || image.empty()) return makeError(name, "cannot write an empty image");
    if (image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
        return makeError(name, "image size " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                                   " does not match its " + std::to_string(image.pixels.size()) + " pixels");
    return okStatus();
}

}  // namespace

Image<glm::u8vec4> encodeSrgb8(const Image<glm::vec4>& linearRgba) {
    Image<glm::u8vec4> out(linearRgba.width, linearRgba.height);
    out.pixels.resize(linearRgba.pixels.size());
    const SrgbTable& srgb = srgbTable();
    for (std::size_t i = 0; i < linearRgba.pixels.size(); ++i) {
        const glm::vec4& p = linearRgba.pixels[i];
        out.pixels[i] = glm::u8vec4(srgb(p.r), srgb(p.g), srgb(p.b), encodeLinear(p.a));
    }
    return out;
}

Status writePng(const std::filesystem::path& path, const Image<glm::vec4>& linearRgba, bool withAlpha) {
    if (auto st = checkShape(path, linearRgba); !st) return st;
    return writePng(path, encodeSrgb8(linearRgba), withAlpha);
}

Status writePng(const std::filesystem::path& path, const Image<glm::u8vec4>& srgba8, bool withAlpha) {
    if (auto st = checkShape(path, srgba8); !st) return st;
    const int channels = withAlpha ? 4 : 3;
    std::vector<png_byte> bytes;
    bytes.reserve(srgba8.pixels.size() * std::size_t(channels));
    for (const glm::u8vec4& p : srgba8.pixels)
        for (int c = 0; c < channels; ++c) bytes.push_back(p[c]);
    return writeEncoded(path, srgba8.width, srgba8.height, channels, bytes);
}

}  // namespace meniscus
