// Small helpers shared by the file-format code (internal to src/io).
#pragma once

#include <algorithm>
#include <cctype>
#include <charconv>
#include <exception>
#include <new>
#include <string>
#include <string_view>
#include <utility>

#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::io_util {

inline std::string lower(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return out;
}

inline bool endsWith(std::string_view s, std::string_view suffix) {
    return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

// A number as text: decimal, exponent, "nan", "inf" (any case), optional sign.
inline bool parseNumber(std::string_view token, double& out) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty() || token.front() == '+') return false;
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, out);
    return ec == std::errc() && ptr == end;
}

// A token quoted for a message: at most 60 characters, control bytes as '?'
// (keeps messages readable when a "line" is really binary junk).
inline std::string quoteShort(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 60)) out += (static_cast<unsigned char>(c) < 32 || c == 127) ? '?' : c;
    if (s.size() > 60) out += "...";
    return "'" + out + "'";
}

// Walks the lines of a text, counting them from 1.
class Lines {
public:
    explicit Lines(std::string_view text) : text_(text) {
        if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);  // UTF-8 byte order mark
    }
    bool next(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        const std::size_t nl = text_.find('\n', pos_);
        const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
        line = text_.substr(pos_, end - pos_);
        pos_ = nl == std::string_view::npos ? text_.size() : nl + 1;
        ++number_;
        return true;
    }
    std::size_t number() const { return number_; }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t number_ = 0;
};

// Thrown by a parser deep inside its reading code for malformed input; caught
// by guardParse at the API boundary and returned as an Error.
struct ParseFailure {
    std::string message;
};
[[noreturn]] inline void fail(std::string message) { throw ParseFailure{std::move(message)}; }

// Runs a parser body and turns any exception into an Error naming the file, so
// nothing escapes the library's API. `format` reads like "PLY" or "BGEO".
template <class Fn>
Result<ParticleSet> guardParse(const std::string& name, const char* format, Fn&& body) {
    try {
        return body();
    } catch (const ParseFailure& f) {
        return makeError(name, f.message);
    } catch (const std::bad_alloc&) {
        return makeError(name, std::string("out of memory reading ") + format + " data");
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot read ") + format + " data: " + e.what());
    }
}

}  // namespace meniscus::io_util
