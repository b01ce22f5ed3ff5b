// Small helpers shared by the file-format code (internal to src/io).
#pragma once

#include <algorithm>
#include <cctype>
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
