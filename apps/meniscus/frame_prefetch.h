// Frames read on a worker thread ahead of the one in use: the viewer's, so
// that playing a sequence does not stall on the disk (a window that wraps
// round, frames kept until they leave it), and `meniscus render`'s, so that
// frame k + 1 is read while frame k renders (read once, in order: take()).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "common.h"

namespace meniscus::app {

class FramePrefetch {
public:
    // A read frame, or why it could not be read.
    struct Loaded {
        std::shared_ptr<const ParticleSet> set;  // null on error
        std::string error;                       // failure.describe()
        Error failure;                           // the reader's own error (file, message, usage)
    };
    // Reads frames of `frames` on its own thread; `ready` is called (from that
    // thread) after each frame is read, e.g. to wake the window's loop.
    // `seed` is frame `seedIndex` already read (the viewer's first frame,
    // which opening the input read), so it is not read twice.
    // `wrap`: the window wraps round past the last frame (a viewer plays in a
    // loop); without it the frames after the last are not read, and without
    // a seed frame `seedIndex` is one the caller has already (not read).
    FramePrefetch(Frames frames, std::function<void()> ready, std::size_t ahead = 4,
                  std::shared_ptr<const ParticleSet> seed = nullptr, std::size_t seedIndex = 0, bool wrap = true);
    ~FramePrefetch();  // stops and joins the worker (a read in progress finishes first)
    FramePrefetch(const FramePrefetch&) = delete;
    FramePrefetch& operator=(const FramePrefetch&) = delete;

    // Frame i is wanted now, and the `ahead` after it (wrapping): the worker
    // reads them in that order and forgets the frames outside that window.
    void want(std::size_t i);
    // Frame i if it has been read, else nothing (yet).
    std::optional<Loaded> get(std::size_t i);
    // Frame i, waiting for the worker to read it.
    Loaded wait(std::size_t i);
    // Frame i, waiting for it, as the only owner (taken out of the cache);
    // the worker goes on with the `ahead` frames after it, so that no more
    // than `ahead` read frames wait beside the one taken. For a sequence read
    // once, in order (frame i is read again if taken twice).
    Result<ParticleSet> take(std::size_t i);
    // From now on the window starts at frame i, which is not read yet (the
    // caller has it): the worker reads the `ahead` frames after it.
    void skip(std::size_t i);

    const Frames& frames() const { return frames_; }

private:
    bool inWindow(std::size_t k) const;  // under mutex_
    void run();
    const Frames frames_;
    const std::function<void()> ready_;
    const std::size_t ahead_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::size_t wanted_ = 0;
    bool stop_ = false;
    const bool wrap_;
    std::size_t skipped_ = SIZE_MAX;  // a frame in the window the caller has: not read
    std::map<std::size_t, Loaded> cache_;
    std::thread worker_;  // last: started once the rest exists
};

}  // namespace meniscus::app
