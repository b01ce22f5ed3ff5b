// A text's lines, one at a time, for the small line-based parsers of the
// modules (the shader include resolver, the cgroup files of the memory
// budget, a PLY header's element counts). C++ only.
#pragma once

#include <cstddef>
#include <string_view>

namespace meniscus::shared {

// Lines of `text` separated by '\n', without it; the last line counts even
// without a '\n' after it, and an empty text has none:
//   TextLines lines(text);
//   for (std::string_view line; lines.next(line);) ...
class TextLines {
public:
    explicit TextLines(std::string_view text) : text_(text) {}
    // The next line into `line`; false (and `line` unchanged) after the last.
    bool next(std::string_view& line) {
        if (at_ >= text_.size()) return false;
        std::size_t end = text_.find('\n', at_);
        if (end == std::string_view::npos) end = text_.size();
        line = text_.substr(at_, end - at_);
        at_ = end + 1;
        return true;
    }

private:
    std::string_view text_;
    std::size_t at_ = 0;
};

}  // namespace meniscus::shared
