// Frames read ahead on a worker thread (frame_prefetch.h).
#include "frame_prefetch.h"

#include <utility>

namespace meniscus::app {

FramePrefetch::FramePrefetch(Frames frames, std::function<void()> ready, std::size_t ahead,
                             std::shared_ptr<const ParticleSet> seed, std::size_t seedIndex, bool wrap)
    : frames_(std::move(frames)),
      ready_(std::move(ready)),
      ahead_(ahead),
      wanted_(seedIndex),
      wrap_(wrap),
      skipped_(!wrap && !seed ? seedIndex : SIZE_MAX),
      cache_(seed ? std::map<std::size_t, Loaded>{{seedIndex, Loaded{std::move(seed), {}, {}}}}
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
    if (!wrap_) return k < n && k >= wanted_ && k - wanted_ <= ahead_;
    return n > 0 && (k + n - wanted_) % n <= ahead_;
}

void FramePrefetch::want(std::size_t i) {
    {
        std::lock_guard lock(mutex_);
        wanted_ = i;
        if (skipped_ == i) skipped_ = SIZE_MAX;  // wanted after all: read it
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

Result<ParticleSet> FramePrefetch::take(std::size_t i) {
    Loaded loaded = wait(i);
    {
        std::lock_guard lock(mutex_);
        cache_.erase(i);
        skipped_ = i;  // taken: not to be read again while the window starts there
    }
    if (!loaded.set) return loaded.failure;
    // The worker made it and no longer holds it: a copy only if a caller of
    // get() or wait() still does.
    if (loaded.set.use_count() == 1)
        return std::move(const_cast<ParticleSet&>(*loaded.set));  // made non-const in run()
    return ParticleSet(*loaded.set);
}

void FramePrefetch::skip(std::size_t i) {
    {
        std::lock_guard lock(mutex_);
        wanted_ = i;
        skipped_ = i;
        std::erase_if(cache_, [this](const auto& entry) { return !inWindow(entry.first); });
    }
    changed_.notify_all();
}

void FramePrefetch::run() {
    const std::size_t n = frames_.count();
    std::unique_lock lock(mutex_);
    while (!stop_) {
        // The first frame of the window, in order, not read yet.
        std::optional<std::size_t> next;
        for (std::size_t d = 0; d <= ahead_ && d < n && !next; ++d) {
            const std::size_t k = wrap_ ? (wanted_ + d) % n : wanted_ + d;
            if (k < n && k != skipped_ && !cache_.count(k)) next = k;
        }
        if (!next) {
            changed_.wait(lock);
            continue;
        }
        lock.unlock();
        auto set = frames_.loadChecked(*next);
        Loaded loaded;
        // Made non-const, held as const: take() may move it out once it alone holds it.
        if (set) loaded.set = std::make_shared<ParticleSet>(std::move(*set));
        else {
            loaded.failure = set.error();
            loaded.error = loaded.failure.describe();
        }
        lock.lock();
        if (inWindow(*next)) cache_[*next] = std::move(loaded);
        lock.unlock();
        changed_.notify_all();
        if (ready_) ready_();
        lock.lock();
    }
}

}  // namespace meniscus::app
