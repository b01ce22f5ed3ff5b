// The viewer's frames, read on a worker thread ahead of the one on screen, so
// that playing a sequence does not stall on the disk.
#pragma once

#include <condition_variable>
#include <cstddef>
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
        std::string error;
    };
    // Reads frames of `frames` on its own thread; `ready` is called (from that
    // thread) after each frame is read, e.g. to wake the window's loop.
    // `seed` is frame `seedIndex` already read (the viewer's first frame,
    // which opening the input read), so it is not read twice.
    FramePrefetch(Frames frames, std::function<void()> ready, std::size_t ahead = 4,
                  std::shared_ptr<const ParticleSet> seed = nullptr, std::size_t seedIndex = 0);
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
    std::map<std::size_t, Loaded> cache_;
    std::thread worker_;  // last: started once the rest exists
};

}  // namespace meniscus::app
