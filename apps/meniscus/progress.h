// A one-line progress bar with ETA on stderr, shown only on a terminal.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include <unistd.h>

class ProgressBar {
public:
    ProgressBar(std::size_t total, std::string label)
        : total_(total), label_(std::move(label)), tty_(::isatty(STDERR_FILENO) == 1),
          start_(std::chrono::steady_clock::now()) {}

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
    std::chrono::steady_clock::time_point start_;
};
