// Movies: H.264 video in an MP4 file, through FFmpeg's libraries (libavcodec's
// libx264 encoder, libavformat's MP4 muxer, libswscale for the colour
// conversion). The module meniscus_video (src/video/) is built when CMake
// finds them (Debian: libavcodec-dev, libavformat-dev, libswscale-dev).
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>

#include <glm/ext/vector_uint4_sized.hpp>

#include "meniscus/params.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

struct VideoParams {
    double fps = defaults::kVideoFps;  // frames per second of the movie (> 0, at most 1000)
    int crf = defaults::kVideoCrf;     // x264's constant rate factor: 0 lossless .. 51 worst; 18 looks lossless
};

// Writes frames, in the order given, to an MP4 file: H.264 (High profile,
// yuv420p, BT.709 limited range, as players expect), one frame every 1/fps
// seconds. The file is written under a temporary name and renamed by
// finish(), so an error, an exception or a writer dropped before finish()
// leaves no partial movie (PendingFile, io.h). Never throws.
class VideoWriter {
public:
    // An encoder for width x height frames; both even (4:2:0 chroma has one
    // sample per 2x2 pixels). An error names the file and the problem (odd
    // size, bad fps or crf, no H.264 encoder in this FFmpeg, unwritable place).
    static Result<VideoWriter> open(const std::filesystem::path& path, int width, int height,
                                    const VideoParams& params = {});
    VideoWriter(VideoWriter&&) noexcept;
    VideoWriter& operator=(VideoWriter&&) noexcept;
    ~VideoWriter();

    // One frame, 8-bit sRGB as writePng writes it (encodeSrgb8 of the render);
    // alpha is ignored (a movie has none). Its size must be the writer's.
    Status add(const Image<glm::u8vec4>& srgba8);
    // Drains the encoder, writes the MP4 index at the front of the file (so it
    // plays while downloading) and renames the file onto its name.
    Status finish();
    std::size_t frames() const;

private:
    struct Impl;
    explicit VideoWriter(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace meniscus
