// Frames read ahead on a worker thread (frame_prefetch.h).
#include "frame_prefetch.h"

#include <utility>

namespace meniscus::app {

FramePrefetch::FramePrefetch(Frames frames, std::function<void()> ready, std::size_t ahead,
                             std::shared_ptr<const ParticleSet> seed, std::size_t seedIndex)
    : frames_(std::move(frames)),
      ready_(std::move(ready)),
      ahead_(ahead),
      wanted_(seedIndex),
      cache_(seed ? std::map<std::size_t, Loaded>{{seedIndex, Loaded{std::move(seed), {}}}}
                  : std::map<std::size_t, Loaded>{}),
      worker_([this] { run(); }) {}

FramePrefetch::~FramePrefetch() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    changed_.notify_all();
    worker_.join();
}

bool FramePrefetch::inWindow(std::size_t k) const {
    const std::size_t n = frames_.count();
    return n > 0 && (k + n - wanted_) % n <= ahead_;
}

void FramePrefetch::want(std::size_t i) {
    {
        std::lock_guard lock(mutex_);
        wanted_ = i;
        std::erase_if(cache_, [this](const auto& entry) { return !inWindow(entry.first); });
    }
    changed_.notify_all();
}

std::optional<FramePrefetch::Loaded> FramePrefetch::get(std::size_t i) {
    std::lock_guard lock(mutex_);
    const auto it = cache_.find(i);
    if (it == cache_.end()) return std::nullopt;
    return it->second;
}

FramePrefetch::Loaded FramePrefetch::wait(std::size_t i) {
    want(i);
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return cache_.count(i) > 0; });
    return cache_.at(i);
}

void FramePrefetch::run() {
    const std::size_t n = frames_.count();
    std::unique_lock lock(mutex_);
    while (!stop_) {
        // The first frame of the window, in order, not read yet.
        std::optional<std::size_t> next;
        for (std::size_t d = 0; d <= ahead_ && d < n && !next; ++d)
            if (!cache_.count((wanted_ + d) % n)) next = (wanted_ + d) % n;
        if (!next) {
            changed_.wait(lock);
            continue;
        }
        lock.unlock();
        auto set = frames_.loadChecked(*next);
        Loaded loaded;
        if (set) loaded.set = std::make_shared<const ParticleSet>(std::move(*set));
        else loaded.error = set.error().describe();
        lock.lock();
        if (inWindow(*next)) cache_[*next] = std::move(loaded);
        lock.unlock();
        changed_.notify_all();
        if (ready_) ready_();
        lock.lock();
    }
}

}  // namespace meniscus::app
