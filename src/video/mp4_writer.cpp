// VideoWriter (include/meniscus/video.h): H.264 in MP4 through FFmpeg 5's
// send/receive API, the way FFmpeg's doc/examples/mux.c does it.
//
// - Encoder: libx264 when this FFmpeg has it (Debian's does), else any H.264
//   encoder; yuv420p, CRF rate control (x264's `crf` option), preset medium,
//   a keyframe at least every 2 s so players can seek.
// - Colour: the frames are sRGB; swscale converts them to BT.709 limited
//   range Y'CbCr, and the stream says so (primaries, transfer, matrix), so
//   players show the PNG's colours.
// - Container: libavformat's MP4 muxer with +faststart (the index moved to the
//   front when the file is finished), time base 1/fps, frame i at pts i.
// - The file is written to PendingFile's temporary name (io.h) and renamed by
//   finish(); any error or an unfinished writer removes it.
#include "meniscus/video.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <utility>

#include "meniscus/io.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace meniscus {
namespace {

std::string avError(int code) {
    char buf[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, buf, sizeof buf);
    return buf;
}

}  // namespace

struct VideoWriter::Impl {
    std::filesystem::path path;
    PendingFile file;
    AVFormatContext* format = nullptr;
    AVCodecContext* codec = nullptr;
    AVStream* stream = nullptr;
    SwsContext* sws = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* packet = nullptr;
    bool finished = false;
    std::size_t count = 0;
    int width = 0, height = 0;

    Impl(std::filesystem::path p, PendingFile f) : path(std::move(p)), file(std::move(f)) {}
    ~Impl() {
        av_packet_free(&packet);
        av_frame_free(&frame);
        sws_freeContext(sws);
        avcodec_free_context(&codec);
        if (format) {
            if (format->pb) avio_closep(&format->pb);
            avformat_free_context(format);
        }
        // `file` goes last: an unfinished movie's temporary is removed.
    }

    Error fail(const std::string& what) const { return makeError(path.string(), what); }

    // Sends `f` (nullptr: drain) and writes every packet the encoder gives back.
    Status encode(AVFrame* f) {
        int ret = avcodec_send_frame(codec, f);
        if (ret < 0) return fail("H.264 encoding failed: " + avError(ret));
        for (;;) {
            ret = avcodec_receive_packet(codec, packet);
            if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF) return okStatus();
            if (ret < 0) return fail("H.264 encoding failed: " + avError(ret));
            av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
            packet->stream_index = stream->index;
            ret = av_interleaved_write_frame(format, packet);  // takes the packet's data
            if (ret < 0) return fail("cannot write the movie: " + avError(ret));
        }
    }
};

VideoWriter::VideoWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
VideoWriter::VideoWriter(VideoWriter&&) noexcept = default;
VideoWriter& VideoWriter::operator=(VideoWriter&&) noexcept = default;
VideoWriter::~VideoWriter() = default;

std::size_t VideoWriter::frames() const { return impl_ ? impl_->count : 0; }

Result<VideoWriter> VideoWriter::open(const std::filesystem::path& path, int width, int height,
                                      const VideoParams& params) {
    const std::string name = path.string();
    // The caller's settings (Error::usage): the size, the rate and the quality.
    if (width <= 0 || height <= 0 || width % 2 != 0 || height % 2 != 0)
        return makeUsageError(name, "an H.264 movie needs an even width and height, not " + std::to_string(width) + "x" +
                                   std::to_string(height) + " (4:2:0 chroma: one sample per 2x2 pixels)");
    if (!(params.fps > 0.0 && params.fps <= 1000.0))
        return makeUsageError(name, "the frame rate must be in (0, 1000] frames per second, not " +
                                   std::to_string(params.fps));
    if (params.crf < 0 || params.crf > 51)
        return makeUsageError(name, "the CRF must be 0 (lossless) to 51, not " + std::to_string(params.crf));
    try {
        auto pending = PendingFile::begin(path);
        if (!pending) return pending.error();
        auto impl = std::make_unique<Impl>(path, std::move(*pending));
        Impl& v = *impl;
        v.width = width;
        v.height = height;

        av_log_set_level(AV_LOG_ERROR);  // x264's statistics are not for our users' terminals
        const AVCodec* encoder = avcodec_find_encoder_by_name("libx264");
        if (!encoder) encoder = avcodec_find_encoder(AV_CODEC_ID_H264);
        if (!encoder) return v.fail("this FFmpeg has no H.264 encoder (Debian's libavcodec59 has libx264)");
        int ret = avformat_alloc_output_context2(&v.format, nullptr, "mp4", v.file.tmp().c_str());
        if (ret < 0 || !v.format) return v.fail("cannot set up the MP4 muxer: " + avError(ret));
        v.stream = avformat_new_stream(v.format, nullptr);
        v.codec = avcodec_alloc_context3(encoder);
        v.frame = av_frame_alloc();
        v.packet = av_packet_alloc();
        if (!v.stream || !v.codec || !v.frame || !v.packet) return v.fail("out of memory setting up the encoder");

        const AVRational rate = av_d2q(params.fps, 100000);
        v.codec->width = width;
        v.codec->height = height;
        v.codec->pix_fmt = AV_PIX_FMT_YUV420P;
        v.codec->time_base = av_inv_q(rate);
        v.codec->framerate = rate;
        v.codec->gop_size = std::max(1, int(std::lround(2.0 * params.fps)));
        v.codec->color_primaries = AVCOL_PRI_BT709;
        v.codec->color_trc = AVCOL_TRC_BT709;
        v.codec->colorspace = AVCOL_SPC_BT709;
        v.codec->color_range = AVCOL_RANGE_MPEG;
        if (v.format->oformat->flags & AVFMT_GLOBALHEADER) v.codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
        if (std::string(encoder->name) == "libx264") {
            av_opt_set(v.codec->priv_data, "preset", "medium", 0);
            av_opt_set(v.codec->priv_data, "crf", std::to_string(params.crf).c_str(), 0);
        }
        ret = avcodec_open2(v.codec, encoder, nullptr);
        if (ret < 0) return v.fail(std::string("cannot open the ") + encoder->name + " encoder: " + avError(ret));
        ret = avcodec_parameters_from_context(v.stream->codecpar, v.codec);
        if (ret < 0) return v.fail("cannot set up the MP4 stream: " + avError(ret));
        v.stream->time_base = v.codec->time_base;
        v.stream->avg_frame_rate = rate;

        v.frame->format = AV_PIX_FMT_YUV420P;
        v.frame->width = width;
        v.frame->height = height;
        ret = av_frame_get_buffer(v.frame, 0);
        if (ret < 0) return v.fail("out of memory for a frame: " + avError(ret));
        v.sws = sws_getContext(width, height, AV_PIX_FMT_RGBA, width, height, AV_PIX_FMT_YUV420P, SWS_BICUBIC,
                               nullptr, nullptr, nullptr);
        if (!v.sws) return v.fail("cannot set up the colour conversion");
        // sRGB in (full range, BT.709 primaries) -> BT.709 limited-range Y'CbCr out.
        const int* bt709 = sws_getCoefficients(SWS_CS_ITU709);
        sws_setColorspaceDetails(v.sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);

        ret = avio_open(&v.format->pb, v.file.tmp().c_str(), AVIO_FLAG_WRITE);
        if (ret < 0) return v.fail("cannot open for writing: " + avError(ret));
        AVDictionary* options = nullptr;
        av_dict_set(&options, "movflags", "+faststart", 0);
        ret = avformat_write_header(v.format, &options);
        av_dict_free(&options);
        if (ret < 0) return v.fail("cannot write the MP4 header: " + avError(ret));
        return VideoWriter(std::move(impl));
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot start the movie: ") + e.what());
    }
}

Status VideoWriter::add(const Image<glm::u8vec4>& srgba8) {
    if (!impl_) return makeError("", "add on a moved-from VideoWriter");
    Impl& v = *impl_;
    if (v.finished) return v.fail("the movie is already finished");
    if (srgba8.width != v.width || srgba8.height != v.height ||
        srgba8.pixels.size() != std::size_t(v.width) * std::size_t(v.height))
        return v.fail("frame " + std::to_string(v.count) + " is " + std::to_string(srgba8.width) + "x" +
                      std::to_string(srgba8.height) + ", the movie " + std::to_string(v.width) + "x" +
                      std::to_string(v.height));
    int ret = av_frame_make_writable(v.frame);  // the encoder may still hold the last one
    if (ret < 0) return v.fail("out of memory for a frame: " + avError(ret));
    const std::uint8_t* src[1] = {reinterpret_cast<const std::uint8_t*>(srgba8.pixels.data())};
    const int srcStride[1] = {4 * v.width};
    sws_scale(v.sws, src, srcStride, 0, v.height, v.frame->data, v.frame->linesize);
    v.frame->pts = std::int64_t(v.count);
    if (auto st = v.encode(v.frame); !st) return st;
    ++v.count;
    return okStatus();
}

Status VideoWriter::finish() {
    if (!impl_) return makeError("", "finish on a moved-from VideoWriter");
    Impl& v = *impl_;
    if (v.finished) return v.fail("the movie is already finished");
    v.finished = true;
    if (v.count == 0) return v.fail("no frames to write");
    if (auto st = v.encode(nullptr); !st) return st;
    int ret = av_write_trailer(v.format);
    if (ret < 0) return v.fail("cannot finish the MP4 file: " + avError(ret));
    ret = avio_closep(&v.format->pb);
    if (ret < 0) return v.fail("cannot close the movie: " + avError(ret));
    return v.file.commit();
}

}  // namespace meniscus
