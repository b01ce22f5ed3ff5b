// Radiance RGBE pictures (.hdr), for the environment map
// (docs/pipeline.md#environment-map). The format is Greg Ward's: "Real
// Pixels", Graphics Gems II (1991), and the Radiance file format notes
// ("The RADIANCE Picture File Format"):
//  - a text header: the first line "#?RADIANCE" (or "#?RGBE"), then lines of
//    VARIABLE=value (FORMAT=32-bit_rle_rgbe, EXPOSURE=f, ...) and comments,
//    ended by an empty line;
//  - the resolution line, here only the standard orientation "-Y H +X W":
//    H scanlines from the top, each W pixels from the left;
//  - the scanlines, each in one of three encodings:
//    * flat: W pixels of 4 bytes R, G, B, E;
//    * adaptive run-length ("new" RLE, for 8 <= W <= 0x7fff): the bytes
//      2, 2, W >> 8, W & 0xff, then each of the 4 components for the whole
//      scanline as runs: a count byte c > 128 followed by one value repeated
//      c - 128 times, or 0 < c <= 128 followed by c literal values;
//    * "old" RLE: pixels of 4 bytes, where the pixel 1, 1, 1, n repeats the
//      previous pixel n times, n shifted left by 8 more bits for each such
//      repeat pixel that directly follows another.
//  - a pixel (r, g, b, e) is radiance (m + 0.5) 2^(e - 136) per component m
//    (0 when e = 0), Radiance's colr_color; EXPOSURE lines say the pixels were
//    multiplied by that factor (cumulative, so their product), which is
//    divided out here. Other header variables (PRIMARIES, COLORCORR, ...) are
//    ignored: the texels are taken as the linear RGB the OpenEXR maps hold.
// FORMAT=32-bit_rle_xyze (CIE XYZ pixels) is refused with an error saying so
// (convert the map to RGB): XYZ would need Radiance's own primaries and white
// to turn into the renderer's linear RGB, which no map in the common use needs.
//
// Why not stb_image (Debian's libstb-dev, which reads .hdr): its HDR loader
// (v2.27 there) reads a truncated file as zero bytes instead of failing (and
// a zero count in a truncated run loops forever: CVE-2021-42715), allocates
// the whole image from the header's size before any pixel exists, reads
// neither EXPOSURE nor old-style runs; see docs/layout.md.
#include "radiance_hdr.h"

#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace meniscus::io {

namespace {

// A cursor over the bytes; every read checks what is left.
struct Bytes {
    const std::uint8_t* p;
    std::size_t size;
    std::size_t at = 0;
    std::size_t left() const { return size - at; }
};

// One header line without its '\n' (and a '\r' before it); false at the end
// of the bytes without a '\n'.
bool nextLine(Bytes& b, std::string_view& line) {
    if (b.left() == 0) return false;
    const void* nl = std::memchr(b.p + b.at, '\n', b.left());
    if (!nl) return false;
    const std::size_t end = std::size_t(static_cast<const std::uint8_t*>(nl) - b.p);
    std::size_t stop = end;
    if (stop > b.at && b.p[stop - 1] == '\r') --stop;
    line = std::string_view(reinterpret_cast<const char*>(b.p + b.at), stop - b.at);
    b.at = end + 1;
    return true;
}

// A positive decimal integer no larger than `limit`; false otherwise.
bool parseCount(std::string_view s, long long limit, long long& out) {
    if (s.empty() || s.size() > 9) return false;
    long long v = 0;
    for (char c : s) {
        if (c < '0' || c > '9') return false;
        v = v * 10 + (c - '0');
    }
    if (v <= 0 || v > limit) return false;
    out = v;
    return true;
}

// Whitespace-separated tokens of a line.
std::vector<std::string_view> tokens(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size() && out.size() < 8) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

// Radiance's colr_color: (m + 0.5) 2^(e - 136), 0 for e = 0. Exact in float.
float component(std::uint8_t m, std::uint8_t e) {
    return e == 0 ? 0.0f : std::ldexp(float(m) + 0.5f, int(e) - 136);
}

// Decodes one scanline of `w` pixels into `rgbe` (4 bytes a pixel), or only
// walks over it when `rgbe` is null; an empty string when it is whole, else
// what is wrong.
std::string scanline(Bytes& b, int w, std::uint8_t* rgbe) {
    std::uint8_t scratch[4];
    auto put = [&](int x, int c, std::uint8_t v) {
        if (rgbe) rgbe[4 * x + c] = v;
    };
    if (b.left() < 4) return "the pixels end early";
    const std::uint8_t* h = b.p + b.at;
    // Adaptive RLE: 2, 2, then the width (its high byte < 128).
    if (w >= 8 && w <= 0x7fff && h[0] == 2 && h[1] == 2 && (h[2] & 0x80) == 0) {
        if ((int(h[2]) << 8 | int(h[3])) != w) return "a run-length scanline of the wrong length";
        b.at += 4;
        for (int c = 0; c < 4; ++c)
            for (int x = 0; x < w;) {
                if (b.left() < 1) return "the pixels end early";
                const int code = b.p[b.at++];
                if (code > 128) {
                    const int n = code - 128;
                    if (x + n > w) return "a run past the end of its scanline";
                    if (b.left() < 1) return "the pixels end early";
                    const std::uint8_t v = b.p[b.at++];
                    for (int k = 0; k < n; ++k) put(x++, c, v);
                } else {
                    if (code == 0 || x + code > w) return "a run past the end of its scanline";
                    if (b.left() < std::size_t(code)) return "the pixels end early";
                    for (int k = 0; k < code; ++k) put(x++, c, b.p[b.at++]);
                }
            }
        return {};
    }
    // Flat pixels, with old-style repeats.
    int shift = 0;
    for (int x = 0; x < w;) {
        if (b.left() < 4) return "the pixels end early";
        const std::uint8_t* q = b.p + b.at;
        b.at += 4;
        if (q[0] == 1 && q[1] == 1 && q[2] == 1) {
            if (x == 0) return "a repeat with no pixel before it in its scanline";
            if (shift > 16) return "a repeat past the end of its scanline";
            const long long n = (long long)q[3] << shift;
            if (n > w - x) return "a repeat past the end of its scanline";
            if (rgbe) {
                std::memcpy(scratch, rgbe + 4 * (x - 1), 4);
                for (long long k = 0; k < n; ++k) std::memcpy(rgbe + 4 * (x + k), scratch, 4);
            }
            x += int(n);
            shift += 8;
        } else {
            if (rgbe) std::memcpy(rgbe + 4 * x, q, 4);
            ++x;
            shift = 0;
        }
    }
    return {};
}

}  // namespace

Result<EnvironmentImage> decodeRadianceHdr(const std::uint8_t* data, std::size_t size, const std::string& name) {
    Bytes b{data, size};
    auto fail = [&](const std::string& what) { return makeError(name, "environment map (Radiance .hdr): " + what); };
    std::string_view line;
    if (!nextLine(b, line) || (line != "#?RADIANCE" && line != "#?RGBE"))
        return fail("not a Radiance picture (the first line is not #?RADIANCE or #?RGBE)");
    double exposure = 1.0;
    for (;;) {
        if (!nextLine(b, line)) return fail("the header has no end (an empty line)");
        if (line.empty()) break;
        if (line.substr(0, 7) == "FORMAT=") {
            const std::string_view f = line.substr(7);
            if (f == "32-bit_rle_rgbe") {
            } else if (f == "32-bit_rle_xyze")
                return fail("CIE XYZ pixels (FORMAT=32-bit_rle_xyze) are not read; convert the map to RGB");
            else return fail("unknown pixel format " + std::string(f.substr(0, 40)));
        } else if (line.substr(0, 9) == "EXPOSURE=") {
            // Cumulative: the pixels were multiplied by every one of them.
            const std::string s(line.substr(9, 40));
            char* end = nullptr;
            const double e = std::strtod(s.c_str(), &end);
            if (end == s.c_str() || !std::isfinite(e) || e <= 0.0)
                return fail("an EXPOSURE that is not a positive number: " + s);
            exposure *= e;
        }
    }
    // A picture without a FORMAT line is RGBE, the format's default.
    if (!nextLine(b, line)) return fail("no resolution line");
    const std::vector<std::string_view> t = tokens(line);
    if (t.size() != 4) return fail("a resolution line that is not \"-Y H +X W\": " + std::string(line.substr(0, 40)));
    if (t[0] != "-Y" || t[2] != "+X")
        return fail("the orientation " + std::string(t[0]) + " " + std::string(t[2]) +
                    " is not read (only the standard -Y H +X W: scanlines from the top, pixels from the left)");
    long long h = 0, w = 0;
    if (!parseCount(t[1], 1000000000, h) || !parseCount(t[3], 1000000000, w))
        return fail("a resolution line with a size that is not a positive number: " + std::string(line.substr(0, 40)));
    if (w > kMaxEnvironmentWidth || h > kMaxEnvironmentHeight)
        return fail(std::to_string(w) + "x" + std::to_string(h) + " pixels, more than the limit of " +
                    std::to_string(kMaxEnvironmentWidth) + "x" + std::to_string(kMaxEnvironmentHeight));
    const int W = int(w), H = int(h);
    // First only walk over every scanline: nothing is allocated for the image
    // before the bytes were seen to hold all of it.
    const std::size_t pixelsAt = b.at;
    for (int y = 0; y < H; ++y) {
        const std::string what = scanline(b, W, nullptr);
        if (!what.empty()) return fail(what + " (scanline " + std::to_string(y) + " of " + std::to_string(H) + ")");
    }
    b.at = pixelsAt;
    EnvironmentImage image;
    image.width = W;
    image.height = H;
    image.rgb.assign(std::size_t(W) * std::size_t(H) * 3, 0.0f);
    std::vector<std::uint8_t> row(std::size_t(W) * 4);
    for (int y = 0; y < H; ++y) {
        (void)scanline(b, W, row.data());  // whole: walked over above
        float* out = image.rgb.data() + std::size_t(y) * std::size_t(W) * 3;
        for (int x = 0; x < W; ++x) {
            const std::uint8_t* q = row.data() + 4 * x;
            for (int c = 0; c < 3; ++c) {
                const float v = float(double(component(q[c], q[3])) / exposure);
                out[3 * x + c] = std::isfinite(v) && v > 0.0f ? v : 0.0f;
            }
        }
    }
    return image;
}

}  // namespace meniscus::io
