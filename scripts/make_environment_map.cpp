// Writes the test environment map tests/data/environment/sky_128x64.exr: an
// equirectangular linear RGB picture (docs/pipeline.md#environment-map) that
// is easy to recognise in a render: a sky from a warm horizon to a deep blue
// zenith, a bright sun (radiance 40) and, below the horizon, green ground with
// a dark stripe every 16 columns (the rotation shows in the stripes).
// Build and run: scripts/make_environment_map.sh.
#include <cmath>
#include <cstdio>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUT.exr\n", argv[0]);
        return 2;
    }
    const int W = 128, H = 64;
    std::vector<float> rgb(std::size_t(W) * H * 3);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const float u = (float(i) + 0.5f) / W, v = (float(j) + 0.5f) / H;
            float r, g, b;
            if (v < 0.5f) {  // sky: t = 0 at the horizon, 1 at the zenith
                const float t = 1.0f - 2.0f * v;
                r = 1.0f * (1.0f - t) + 0.08f * t;
                g = 0.65f * (1.0f - t) + 0.18f * t;
                b = 0.40f * (1.0f - t) + 0.55f * t;
                const float du = u - 0.30f, dv = v - 0.30f;  // the sun
                if (du * du + dv * dv < 0.0006f) r = g = b = 40.0f;
            } else {  // ground
                const bool stripe = (i / 8) % 2 == 0 && (i % 16) < 2;
                r = stripe ? 0.02f : 0.10f;
                g = stripe ? 0.04f : 0.30f;
                b = stripe ? 0.02f : 0.08f;
            }
            float* p = &rgb[(std::size_t(j) * W + i) * 3];
            p[0] = r;
            p[1] = g;
            p[2] = b;
        }
    Imf::Header header(W, H);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb.data() + c), 3 * sizeof(float),
                                       std::size_t(W) * 3 * sizeof(float)));
    }
    Imf::OutputFile file(argv[1], header);
    file.setFrameBuffer(fb);
    file.writePixels(H);
    return 0;
}
