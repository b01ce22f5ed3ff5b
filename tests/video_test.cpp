// Movies (include/meniscus/video.h): the writer's MP4 decoded back with
// FFmpeg's own demuxer and decoder (frame count, size, pixels close to what
// went in); the CLI's `render SEQUENCE -o out.mp4` against its PNGs; errors
// leave no file.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "meniscus/io.h"
#include "meniscus/video.h"
#include "test_util.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

namespace meniscus::video_test_local {
namespace {

namespace fs = std::filesystem;

struct Decoded {
    int width = 0, height = 0, frames = 0;
    double fps = 0.0;
    std::vector<Image<glm::u8vec4>> rgba;  // every frame, RGBA 8-bit (full range, as the PNG)
};

// Every frame of `path` through libavformat + libavcodec, converted back to
// RGBA by swscale (BT.709 limited range in, full range out).
Decoded decode(const fs::path& path) {
    Decoded d;
    AVFormatContext* fmt = nullptr;
    if (avformat_open_input(&fmt, path.c_str(), nullptr, nullptr) < 0) return d;
    avformat_find_stream_info(fmt, nullptr);
    const int si = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    EXPECT_GE(si, 0);
    if (si < 0) return d;
    AVStream* st = fmt->streams[si];
    EXPECT_EQ(st->codecpar->codec_id, AV_CODEC_ID_H264);
    d.fps = av_q2d(st->avg_frame_rate);
    const AVCodec* dec = avcodec_find_decoder(st->codecpar->codec_id);
    AVCodecContext* ctx = avcodec_alloc_context3(dec);
    avcodec_parameters_to_context(ctx, st->codecpar);
    avcodec_open2(ctx, dec, nullptr);
    d.width = ctx->width;
    d.height = ctx->height;
    AVPacket* pkt = av_packet_alloc();
    AVFrame* frame = av_frame_alloc();
    SwsContext* sws = nullptr;
    auto drain = [&] {
        while (avcodec_receive_frame(ctx, frame) == 0) {
            ++d.frames;
            if (!sws) {
                sws = sws_getContext(frame->width, frame->height, AVPixelFormat(frame->format), frame->width,
                                     frame->height, AV_PIX_FMT_RGBA, SWS_BICUBIC, nullptr, nullptr, nullptr);
                const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
                sws_setColorspaceDetails(sws, bt709, 0, bt709, 1, 0, 1 << 16, 1 << 16);
            }
            Image<glm::u8vec4> img(frame->width, frame->height);
            std::uint8_t* dst[1] = {reinterpret_cast<std::uint8_t*>(img.pixels.data())};
            const int dstStride[1] = {4 * frame->width};
            sws_scale(sws, frame->data, frame->linesize, 0, frame->height, dst, dstStride);
            d.rgba.push_back(std::move(img));
        }
    };
    while (av_read_frame(fmt, pkt) >= 0) {
        if (pkt->stream_index == si) avcodec_send_packet(ctx, pkt);
        av_packet_unref(pkt);
        drain();
    }
    avcodec_send_packet(ctx, nullptr);
    drain();
    sws_freeContext(sws);
    av_frame_free(&frame);
    av_packet_free(&pkt);
    avcodec_free_context(&ctx);
    avformat_close_input(&fmt);
    return d;
}

// Mean absolute difference of R, G, B over the image, 8-bit units.
double meanAbsDiff(const Image<glm::u8vec4>& a, const Image<glm::u8vec4>& b) {
    EXPECT_EQ(a.size(), b.size());
    double sum = 0.0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        for (int c = 0; c < 3; ++c) sum += std::abs(int(a.pixels[i][c]) - int(b.pixels[i][c]));
    return sum / double(3 * std::max<std::size_t>(1, a.size()));
}

// A smooth test picture that changes with k: colour ramps and a moving disc.
Image<glm::u8vec4> picture(int w, int h, int k) {
    Image<glm::u8vec4> img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float dx = float(x - 20 - 4 * k), dy = float(y - h / 2);
            const bool disc = dx * dx + dy * dy < 100.0f;
            img.at(x, y) = glm::u8vec4(disc ? 240 : 40 + 150 * x / w, disc ? 60 : 50 + 150 * y / h, 120, 255);
        }
    return img;
}

// A PNG of ours (RGB or RGBA, 8-bit) as RGBA.
Image<glm::u8vec4> readPngRgba8(const fs::path& path) {
    const test::PngData png = test::readPng(path);
    Image<glm::u8vec4> img(png.width, png.height);
    const std::size_t n = img.size(), channels = n ? png.bytes.size() / n : 0;
    if (channels < 3) return {};
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t* p = &png.bytes[i * channels];
        img.pixels[i] = glm::u8vec4(p[0], p[1], p[2], channels == 4 ? p[3] : 255);
    }
    return img;
}

std::vector<fs::path> listDir(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename());
    return out;
}

TEST(Video, WritesEveryFrameInOrderAndDecodesBackClose) {
    const fs::path dir = test::tempDir() / "video_frames";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const int W = 96, H = 64, N = 12;
    auto movie = VideoWriter::open(dir / "m.mp4", W, H, VideoParams{24.0, 18});
    ASSERT_TRUE(movie) << movie.error().describe();
    for (int k = 0; k < N; ++k) ASSERT_TRUE(movie->add(picture(W, H, k)));
    EXPECT_EQ(movie->frames(), std::size_t(N));
    EXPECT_FALSE(fs::exists(dir / "m.mp4"));  // not before finish()
    ASSERT_TRUE(movie->finish());
    EXPECT_EQ(listDir(dir), std::vector<fs::path>{"m.mp4"});  // no temporary left
    const Decoded d = decode(dir / "m.mp4");
    EXPECT_EQ(d.frames, N);
    EXPECT_EQ(d.width, W);
    EXPECT_EQ(d.height, H);
    EXPECT_NEAR(d.fps, 24.0, 1e-6);
    ASSERT_EQ(d.rgba.size(), std::size_t(N));
    // In order and close: each decoded frame is nearest to its own picture.
    for (int k = 0; k < N; ++k) {
        const double own = meanAbsDiff(d.rgba[k], picture(W, H, k));
        EXPECT_LT(own, 3.0) << "frame " << k;
        if (k > 0) {
            EXPECT_LT(own, meanAbsDiff(d.rgba[k], picture(W, H, k - 1))) << "frame " << k;
        }
    }
    // A second write replaces the file whole.
    auto again = VideoWriter::open(dir / "m.mp4", W, H);
    ASSERT_TRUE(again);
    ASSERT_TRUE(again->add(picture(W, H, 0)));
    ASSERT_TRUE(again->finish());
    EXPECT_EQ(decode(dir / "m.mp4").frames, 1);
}

TEST(Video, ErrorsNameTheFileAndLeaveNothing) {
    const fs::path dir = test::tempDir() / "video_errors";
    fs::remove_all(dir);
    fs::create_directories(dir);
    auto odd = VideoWriter::open(dir / "odd.mp4", 95, 64);
    ASSERT_FALSE(odd);
    EXPECT_NE(odd.error().describe().find("odd.mp4: an H.264 movie needs an even width and height, not 95x64"),
              std::string::npos)
        << odd.error().describe();
    EXPECT_FALSE(VideoWriter::open(dir / "a.mp4", 64, 64, VideoParams{0.0, 18}));
    EXPECT_FALSE(VideoWriter::open(dir / "a.mp4", 64, 64, VideoParams{30.0, 52}));
    auto nowhere = VideoWriter::open(dir / "no" / "such" / "dir.mp4", 64, 64);
    ASSERT_FALSE(nowhere);
    EXPECT_NE(nowhere.error().describe().find("dir.mp4"), std::string::npos) << nowhere.error().describe();
    {
        // A wrong frame size is an error; a writer dropped unfinished leaves no file.
        auto movie = VideoWriter::open(dir / "dropped.mp4", 64, 64);
        ASSERT_TRUE(movie);
        ASSERT_TRUE(movie->add(picture(64, 64, 0)));
        auto wrong = movie->add(picture(32, 64, 1));
        ASSERT_FALSE(wrong);
        EXPECT_NE(wrong.error().describe().find("frame 1 is 32x64, the movie 64x64"), std::string::npos)
            << wrong.error().describe();
    }
    {
        auto empty = VideoWriter::open(dir / "empty.mp4", 64, 64);
        ASSERT_TRUE(empty);
        auto none = empty->finish();
        ASSERT_FALSE(none);
        EXPECT_NE(none.error().describe().find("no frames"), std::string::npos);
    }
    EXPECT_TRUE(listDir(dir).empty()) << listDir(dir).front();
}

// The CLI: a sequence numbered 1, 2, 5 becomes a 3-frame movie at --fps, in
// order, each frame close to the PNG `render` writes for it.
TEST(Video, CliRendersASequenceWithGapsToAnMp4) {
    const fs::path dir = test::tempDir() / "video_cli";
    fs::remove_all(dir);
    fs::create_directories(dir / "in");
    const fs::path data = test::testData("splishsplash/partio");
    fs::copy_file(data / "ParticleData_Fluid_1.bgeo", dir / "in" / "f_1.bgeo");
    fs::copy_file(data / "ParticleData_Fluid_21.bgeo", dir / "in" / "f_2.bgeo");
    fs::copy_file(data / "ParticleData_Fluid_61.bgeo", dir / "in" / "f_5.bgeo");
    const std::string cli = std::string(MENISCUS_CLI) + " render '" + (dir / "in" / "f_*.bgeo").string() +
                            "' --height 90 --backend cpu ";
    std::string out;
    ASSERT_EQ(test::runCommand(cli + "-o '" + (dir / "m.mp4").string() + "' --width 160 --fps 12 --crf 10", &out), 0) << out;
    EXPECT_NE(out.find("wrote " + (dir / "m.mp4").string() + " (3 frames, H.264, 12 fps)"), std::string::npos) << out;
    ASSERT_EQ(test::runCommand(cli + "-o '" + (dir / "p_%04d.png").string() + "' --width 160 --renumber", &out), 0) << out;
    const Decoded d = decode(dir / "m.mp4");
    EXPECT_EQ(d.frames, 3);
    EXPECT_EQ(d.width, 160);
    EXPECT_EQ(d.height, 90);
    EXPECT_NEAR(d.fps, 12.0, 1e-6);
    ASSERT_EQ(d.rgba.size(), 3u);
    for (int k = 0; k < 3; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "p_%04d.png", k);  // --renumber: 0, 1, 2
        const Image<glm::u8vec4> png = readPngRgba8(dir / name);
        ASSERT_EQ(png.width, 160) << name;
        const double own = meanAbsDiff(d.rgba[k], png);
        EXPECT_LT(own, 3.0) << name;
        for (int j = 0; j < 3; ++j) {
            if (j == k) continue;
            EXPECT_LT(own, meanAbsDiff(d.rgba[j], png)) << name << " vs movie frame " << j;
        }
    }
    // Odd sizes and --resume are refused with the reason; no file appears.
    EXPECT_EQ(test::runCommand(cli + "-o '" + (dir / "odd.mp4").string() + "' --width 161", &out), 2);
    EXPECT_NE(out.find("even width and height"), std::string::npos) << out;
    EXPECT_EQ(test::runCommand(cli + "-o '" + (dir / "r.mp4").string() + "' --width 160 --resume", &out), 2);
    EXPECT_FALSE(fs::exists(dir / "odd.mp4"));
    EXPECT_FALSE(fs::exists(dir / "r.mp4"));
}

// The overlapped movie (frame k encoded on a worker while frame k + 1
// renders, the next read ahead) is the sequential one byte for byte
// (MENISCUS_RENDER_OVERLAP=0): x264 is given the same frames in the same
// order, with a fixed thread count.
TEST(Video, TheOverlappedMovieIsTheSequentialMovieByteForByte) {
    const fs::path dir = test::tempDir() / "video_overlap";
    fs::remove_all(dir);
    fs::create_directories(dir / "in");
    const fs::path data = test::testData("splishsplash/partio");
    int k = 0;
    for (int frame : {1, 9, 21, 61})
        fs::copy_file(data / ("ParticleData_Fluid_" + std::to_string(frame) + ".bgeo"),
                      dir / "in" / ("f_" + std::to_string(++k) + ".bgeo"));
    const std::string args = std::string(MENISCUS_CLI) + " render '" + (dir / "in" / "f_*.bgeo").string() +
                             "' --width 160 --height 90 --backend cpu --fps 12 -o ";
    std::string out;
    ASSERT_EQ(test::runCommand("MENISCUS_RENDER_OVERLAP=0 " + args + "'" + (dir / "seq.mp4").string() + "'", &out), 0)
        << out;
    ASSERT_EQ(test::runCommand(args + "'" + (dir / "par.mp4").string() + "'", &out), 0) << out;
    EXPECT_NE(out.find("(4 frames, H.264, 12 fps)"), std::string::npos) << out;
    const auto seq = test::readBytes(dir / "seq.mp4");
    EXPECT_GT(seq.size(), 1000u);
    EXPECT_EQ(seq, test::readBytes(dir / "par.mp4"));
    const Decoded a = decode(dir / "seq.mp4"), b = decode(dir / "par.mp4");
    EXPECT_EQ(a.frames, 4);
    EXPECT_EQ(b.frames, 4);
    ASSERT_FALSE(b.rgba.empty());
    EXPECT_EQ(meanAbsDiff(a.rgba.front(), b.rgba.front()), 0.0);
    EXPECT_GT(meanAbsDiff(b.rgba.front(), b.rgba.back()), 0.0);  // distinct frames
}

// A movie plays at the rate its data carries: a .pvd's timesteps 1/15 s apart
// give 15 fps (SPlisHSPlasH's own output rate), said in the log; --fps still
// wins; frames without time play at the default, and the log says so.
TEST(Video, TheMovieRateComesFromTheData) {
    const fs::path dir = test::tempDir() / "video_rate";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path data = test::testData("splishsplash/partio");
    std::vector<fs::path> files;
    for (const char* n : {"1", "21", "61"}) {
        files.push_back(dir / ("f_" + std::string(n) + ".bgeo"));
        fs::copy_file(data / ("ParticleData_Fluid_" + std::string(n) + ".bgeo"), files.back());
    }
    ASSERT_TRUE(writePvd(dir / "run.pvd", files, {0.0, 1.0 / 15.0, 2.0 / 15.0}).ok());
    const std::string cli = std::string(MENISCUS_CLI) + " render ";
    const std::string look = " --width 160 --height 90 --backend cpu";
    std::string out;
    ASSERT_EQ(test::runCommand(cli + "'" + (dir / "run.pvd").string() + "' -o '" + (dir / "a.mp4").string() + "'" + look,
                               &out),
              0)
        << out;
    EXPECT_NE(out.find("plays at 15 fps (the rate of the input's timesteps"), std::string::npos) << out;
    EXPECT_NEAR(decode(dir / "a.mp4").fps, 15.0, 1e-3);
    ASSERT_EQ(test::runCommand(cli + "'" + (dir / "run.pvd").string() + "' -o '" + (dir / "b.mp4").string() +
                                   "' --fps 24" + look,
                               &out),
              0)
        << out;
    EXPECT_NEAR(decode(dir / "b.mp4").fps, 24.0, 1e-6);
    ASSERT_EQ(test::runCommand(cli + "'" + (dir / "f_*.bgeo").string() + "' -o '" + (dir / "c.mp4").string() + "'" + look,
                               &out),
              0)
        << out;
    EXPECT_NE(out.find("plays at 30 fps (the frames carry no time; --fps sets the rate)"), std::string::npos) << out;
    EXPECT_NEAR(decode(dir / "c.mp4").fps, 30.0, 1e-6);
}

// simulate --render out.mp4 and render SCENE.json -o out.mp4: one movie of
// the simulation's frames at its fps (the small scene: 0.1 s at 50 fps, 6
// frames), the same frames either way; --duration shortens both.
TEST(Video, SimulationsRenderToMovies) {
    const fs::path dir = test::tempDir() / "video_sim";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path scene = test::writeSmallScene(dir);
    const std::string size = " --width 64 --height 48 --backend cpu";
    std::string out;
    ASSERT_EQ(test::runCli("simulate " + test::shellQuote(scene) + " -o " + test::shellQuote(dir / "f/f_%04d.bgeo") +
                               " --render " + test::shellQuote(dir / "movies/sim.mp4") + size,
                           &out),
              0)
        << out;
    EXPECT_NE(out.find("(6 frames, H.264, 50 fps)"), std::string::npos) << out;
    const Decoded a = decode(dir / "movies/sim.mp4");
    EXPECT_EQ(a.frames, 6);
    EXPECT_NEAR(a.fps, 50.0, 1e-6);
    ASSERT_EQ(test::runCli("render " + test::shellQuote(scene) + " -o " + test::shellQuote(dir / "ren.mp4") +
                               " --duration 0.06" + size,
                           &out),
              0)
        << out;
    const Decoded b = decode(dir / "ren.mp4");
    EXPECT_EQ(b.frames, 4);
    EXPECT_NEAR(b.fps, 50.0, 1e-6);
    ASSERT_EQ(b.rgba.size(), 4u);
    // The same pictures, encoded in runs of 6 and 4 frames (x264's choices
    // differ with the run): within the 3 steps a movie keeps of its PNGs.
    for (int k = 0; k < 4; ++k) EXPECT_LT(meanAbsDiff(a.rgba[k], b.rgba[k]), 3.0) << "frame " << k;
    // A movie is written whole: --resume refuses it before simulating.
    EXPECT_EQ(test::runCli("simulate " + test::shellQuote(scene) + " -o " + test::shellQuote(dir / "g/g_%04d.bgeo") +
                               " --render " + test::shellQuote(dir / "r.mp4") + " --resume" + size,
                           &out),
              1);
    EXPECT_NE(out.find("--resume: a movie is written whole"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir / "r.mp4"));
}

}  // namespace
}  // namespace meniscus::video_test_local
