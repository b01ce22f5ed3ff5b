// JSON text read within bounds (include/meniscus/json_text.h).
#include "meniscus/json_text.h"

#include <algorithm>
#include <fstream>
#include <new>
#include <system_error>
#include <vector>

namespace meniscus {

namespace fs = std::filesystem;

std::string byteSizeText(std::uintmax_t bytes) {
    const std::uintmax_t kib = 1024, mib = kib * 1024, gib = mib * 1024;
    if (bytes >= gib && bytes % gib == 0) return std::to_string(bytes / gib) + " GiB";
    if (bytes >= mib && bytes % mib == 0) return std::to_string(bytes / mib) + " MiB";
    if (bytes >= kib && bytes % kib == 0) return std::to_string(bytes / kib) + " KiB";
    return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
}

namespace {

std::string tooLarge(const JsonLimits& limits) {
    return "larger than the " + byteSizeText(limits.maxBytes) + " " + limits.kind + " may be";
}

// The first place the brackets outside strings nest deeper than `maxDepth`,
// as "line L, column C", or empty when they never do.
std::string tooDeepAt(std::string_view text, int maxDepth) {
    int depth = 0;
    bool inString = false, escaped = false;
    std::size_t line = 1, lineStart = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            lineStart = i + 1;
        }
        if (inString) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '{' || c == '[') {
            if (++depth > maxDepth) return "line " + std::to_string(line) + ", column " + std::to_string(i - lineStart + 1);
        } else if (c == '}' || c == ']') {
            // More closing than opening brackets is the parser's to report.
            depth = std::max(depth - 1, 0);
        }
    }
    return {};
}

}  // namespace

Status checkJsonText(std::string_view text, const std::string& name, const JsonLimits& limits) {
    if (text.size() > limits.maxBytes) return makeError(name, tooLarge(limits));
    if (const std::string at = tooDeepAt(text, limits.maxDepth); !at.empty())
        return makeError(name, "nested deeper than " + std::to_string(limits.maxDepth) + " levels (" + at + "); " +
                                   limits.kind + " never needs that");
    return okStatus();
}

Result<std::string> readJsonText(const fs::path& path, const JsonLimits& limits) {
    const std::string name = path.string();
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) return makeError(name, "no such file");
    if (fs::is_directory(st)) return makeError(name, "is a directory, not a file");
    // A regular file's size is known before a byte is read; anything else
    // (a pipe, /dev/zero) is read below until the limit.
    if (fs::is_regular_file(st)) {
        const std::uintmax_t size = fs::file_size(path, ec);
        if (ec) return makeError(name, "cannot be read: " + ec.message());
        if (size > limits.maxBytes) return makeError(name, tooLarge(limits));
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(name, "cannot be opened for reading");
    std::string text;
    try {
        // Pieces of 64 KiB, never more than one past the limit in all.
        constexpr std::size_t kPiece = std::size_t(64) << 10;
        std::vector<char> buffer(kPiece);
        char* piece = buffer.data();
        while (in) {
            const std::uintmax_t room = limits.maxBytes + 1 - text.size();
            in.read(piece, std::streamsize(std::min<std::uintmax_t>(kPiece, room)));
            text.append(piece, std::size_t(in.gcount()));
            if (text.size() > limits.maxBytes) return makeError(name, tooLarge(limits));
        }
        if (in.bad()) return makeError(name, "read error");
    } catch (const std::bad_alloc&) {
        return makeError(name, "out of memory while reading the file");
    }
    if (text.empty()) return makeError(name, "the file is empty");
    if (auto ok = checkJsonText(text, name, limits); !ok) return ok.error();
    return text;
}

}  // namespace meniscus
