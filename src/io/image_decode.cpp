// Texture images (decodeTexture, include/meniscus/geometry.h). PNG: libpng's simplified API
// (png_image_begin_read_from_memory reads the header, png_image_finish_read
// the pixels into our buffer as 8-bit RGB). JPEG: libjpeg (jpeg_mem_src,
// JCS_RGB output), its fatal errors turned into a return by the longjmp its
// documentation prescribes (libjpeg.txt, "Error handling"), from a frame that
// owns no C++ object.
#include "meniscus/geometry.h"
#include "shared/srgb.h"

#include <array>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <optional>
#include <vector>

#include <jpeglib.h>
#include <jerror.h>
#include <png.h>

namespace meniscus {

namespace {

namespace lim = geometry_limits;

// sRGB 8-bit code to linear (IEC 61966-2-1), one table for every texel.
const std::array<float, 256>& srgbTable() { return shared::srgbDecodeTable(); }

std::optional<Error> checkSize(const std::string& name, long long w, long long h) {
    if (w <= 0 || h <= 0) return makeError(name, "has no pixels (" + std::to_string(w) + " x " + std::to_string(h) + ")");
    if (w > lim::kMaxTextureSidePx || h > lim::kMaxTextureSidePx || w * h > lim::kMaxTexturePixels)
        return makeError(name, "is " + std::to_string(w) + " x " + std::to_string(h) + " pixels; a texture is at most " +
                                   std::to_string(lim::kMaxTextureSidePx) + " a side and " +
                                   std::to_string(lim::kMaxTexturePixels) + " pixels");
    return std::nullopt;
}

GeometryTexture toLinear(const std::vector<unsigned char>& rgb8, int w, int h, const std::string& name) {
    GeometryTexture t;
    t.name = name;
    t.width = w;
    t.height = h;
    t.rgb.resize(rgb8.size());
    const std::array<float, 256>& lut = srgbTable();
    for (std::size_t i = 0; i < rgb8.size(); ++i) t.rgb[i] = lut[rgb8[i]];
    return t;
}

Result<GeometryTexture> decodePng(ByteView data, const std::string& name) {
    png_image image;
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, data.data(), data.size()))
        return makeError(name, std::string("is not a PNG it can read: ") + image.message);
    if (auto bad = checkSize(name, image.width, image.height)) {
        png_image_free(&image);
        return *bad;
    }
    image.format = PNG_FORMAT_RGB;  // 8-bit sRGB, no alpha (composited on black)
    std::vector<unsigned char> rgb8(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, rgb8.data(), 0, nullptr))
        return makeError(name, std::string("is a damaged PNG: ") + image.message);
    return toLinear(rgb8, int(image.width), int(image.height), name);
}

struct JpegError {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

void jpegFatal(j_common_ptr c) {
    auto* e = reinterpret_cast<JpegError*>(c->err);
    e->mgr.format_message(c, e->message);
    std::longjmp(e->jump, 1);
}

// Warnings (a corrupt but readable stream) are not printed, but one is an
// error: the data ends before the image does (JWRN_JPEG_EOF). libjpeg would
// fill the rest with grey, so a header of a few bytes claiming 30 million
// pixels would be decoded to a picture of that size (and its floats) from
// nothing; a progressive JPEG reads its whole data in
// jpeg_start_decompress, before the picture's memory is asked for.
void jpegWarning(j_common_ptr c, int level) {
    if (level < 0 && c->err->msg_code == JWRN_JPEG_EOF) jpegFatal(c);
}

// The decode proper, with only C objects in its frame (longjmp skips no
// destructor): the size goes to *w, *h, and `out` is allocated by `grow`
// after the size is checked. Returns false with e->message on a fatal error.
bool jpegRead(ByteView data, JpegError* e, int* w, int* h, bool (*check)(void*, int, int),
              unsigned char* (*grow)(void*, std::size_t), void* ctx, int* stage) {
    jpeg_decompress_struct d;
    d.err = jpeg_std_error(&e->mgr);
    e->mgr.error_exit = jpegFatal;
    e->mgr.emit_message = jpegWarning;
    if (setjmp(e->jump)) {
        jpeg_destroy_decompress(&d);
        return false;
    }
    jpeg_create_decompress(&d);
    jpeg_mem_src(&d, data.data(), static_cast<unsigned long>(data.size()));
    *stage = 1;
    jpeg_read_header(&d, TRUE);
    d.out_color_space = JCS_RGB;
    *w = int(d.image_width);
    *h = int(d.image_height);
    if (!check(ctx, *w, *h)) {
        jpeg_destroy_decompress(&d);
        *stage = 2;
        return false;
    }
    jpeg_start_decompress(&d);
    if (d.output_components != 3) {
        std::snprintf(e->message, sizeof e->message, "%d colour components after conversion to RGB",
                      d.output_components);
        jpeg_destroy_decompress(&d);
        return false;
    }
    const std::size_t row = std::size_t(d.output_width) * 3;
    unsigned char* out = grow(ctx, row * std::size_t(d.output_height));
    if (!out) {
        jpeg_destroy_decompress(&d);
        *stage = 3;
        return false;
    }
    while (d.output_scanline < d.output_height) {
        JSAMPROW r = out + std::size_t(d.output_scanline) * row;
        jpeg_read_scanlines(&d, &r, 1);
    }
    jpeg_finish_decompress(&d);
    jpeg_destroy_decompress(&d);
    return true;
}

struct JpegOut {
    std::string name;
    std::optional<Error> refused;
    std::vector<unsigned char> rgb8;
};

Result<GeometryTexture> decodeJpeg(ByteView data, const std::string& name) {
    JpegOut out{name, std::nullopt, {}};
    JpegError e{};
    int w = 0, h = 0, stage = 0;
    auto check = [](void* ctx, int cw, int ch) {
        auto* o = static_cast<JpegOut*>(ctx);
        o->refused = checkSize(o->name, cw, ch);
        return !o->refused;
    };
    auto grow = [](void* ctx, std::size_t n) -> unsigned char* {
        try {
            auto* o = static_cast<JpegOut*>(ctx);
            o->rgb8.resize(n);
            return o->rgb8.data();
        } catch (...) {
            return nullptr;
        }
    };
    if (!jpegRead(data, &e, &w, &h, check, grow, &out, &stage)) {
        if (out.refused) return *out.refused;
        if (stage == 3) return makeError(name, "ran out of memory while reading");
        return makeError(name, std::string(stage <= 1 ? "is not a JPEG it can read: " : "is a damaged JPEG: ") + e.message);
    }
    return toLinear(out.rgb8, w, h, name);
}

}  // namespace

Result<GeometryTexture> decodeTexture(ByteView data, const std::string& name) {
    try {
        static constexpr unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        if (data.size() >= 8 && std::memcmp(data.data(), kPng, 8) == 0) return decodePng(data, name);
        if (data.size() >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff) return decodeJpeg(data, name);
        return makeError(name, "is not a PNG or a JPEG (the texture formats read)");
    } catch (const std::bad_alloc&) {
        return makeError(name, "ran out of memory while reading");
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot be read: ") + e.what());
    }
}

}  // namespace meniscus
