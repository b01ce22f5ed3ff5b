// A one-line progress bar with ETA on stderr on a terminal; step() prints a
// log line per item instead when stderr is not one (a log file, a batch job).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include <unistd.h>

class ProgressBar {
public:
    ProgressBar(std::size_t total, std::string label)
        : total_(total), label_(std::move(label)), tty_(::isatty(STDERR_FILENO) == 1),
          start_(std::chrono::steady_clock::now()), last_(start_) {}

    void update(std::size_t done) {
        if (!tty_ || total_ == 0) return;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        const double eta = done > 0 ? elapsed / double(done) * double(total_ - done) : 0.0;
        const int width = 30, filled = int(double(width) * double(done) / double(total_));
        std::string bar(std::size_t(filled), '#');
        bar.resize(std::size_t(width), '.');
        std::fprintf(stderr, "\r%s [%s] %zu/%zu  elapsed %s  ETA %s ", label_.c_str(), bar.c_str(), done, total_,
                     clock(elapsed).c_str(), done > 0 ? clock(eta).c_str() : "--:--");
        if (done == total_) std::fprintf(stderr, "\n");
        std::fflush(stderr);
    }

    // Item `done` (1-based) finished: the bar on a terminal, else one line
    // "meniscus: LABEL 3/120 ITEM in 0.41 s, ETA 0:49".
    void step(std::size_t done, const std::string& item) {
        const auto now = std::chrono::steady_clock::now();
        const double took = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        if (tty_) return update(done);
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        const double eta = done > 0 ? elapsed / double(done) * double(total_ - done) : 0.0;
        std::fprintf(stderr, "meniscus: %s %zu/%zu %s in %.2f s, ETA %s\n", label_.c_str(), done, total_, item.c_str(),
                     took, clock(eta).c_str());
        std::fflush(stderr);
    }

private:
    static std::string clock(double seconds) {
        const long s = long(seconds + 0.5);
        char buf[32];
        std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
        return buf;
    }
    std::size_t total_;
    std::string label_;
    bool tty_;
    std::chrono::steady_clock::time_point start_, last_;
};
