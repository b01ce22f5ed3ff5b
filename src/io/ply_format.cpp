// The PLY format: header and element rows (see ply_format.h).
#include "io/ply_format.h"

#include "io/io_util.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>

namespace meniscus::ply {

using io_util::parseNumber;
using io_util::quoteShort;

namespace {

std::optional<ScalarType> scalarTypeFromName(std::string_view n) {
    struct Entry {
        std::string_view name;
        ScalarType type;
    };
    static constexpr Entry kTypes[] = {
        {"char", ScalarType::Int8},       {"int8", ScalarType::Int8},       {"uchar", ScalarType::UInt8},
        {"uint8", ScalarType::UInt8},     {"short", ScalarType::Int16},     {"int16", ScalarType::Int16},
        {"ushort", ScalarType::UInt16},   {"uint16", ScalarType::UInt16},   {"int", ScalarType::Int32},
        {"int32", ScalarType::Int32},     {"uint", ScalarType::UInt32},     {"uint32", ScalarType::UInt32},
        {"float", ScalarType::Float32},   {"float32", ScalarType::Float32}, {"double", ScalarType::Float64},
        {"float64", ScalarType::Float64},
    };
    for (const Entry& e : kTypes)
        if (e.name == n) return e.type;
    return std::nullopt;
}


// ---------------------------------------------------------------- small text helpers

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// Splits on whitespace into `out` (cleared first).
void splitWords(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && isSpace(line[i])) ++i;
        const std::size_t start = i;
        while (i < line.size() && !isSpace(line[i])) ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
}

bool parseCount(std::string_view token, std::uint64_t& out) {
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, out);
    return !token.empty() && ec == std::errc() && ptr == end;
}


// ---------------------------------------------------------------- header

Result<Property> parsePropertyLine(const std::vector<std::string_view>& w, const std::string& name) {
    Property p;
    if (w.size() >= 2 && w[1] == "list") {
        if (w.size() != 5) return makeError(name, "bad PLY header line: 'property list' needs a count type, an item type and a name");
        const auto countType = scalarTypeFromName(w[2]);
        const auto itemType = scalarTypeFromName(w[3]);
        if (!countType) return makeError(name, "unknown PLY property type " + quoteShort(w[2]));
        if (!itemType) return makeError(name, "unknown PLY property type " + quoteShort(w[3]));
        if (!isIntegerType(*countType))
            return makeError(name, "PLY list property '" + std::string(w[4]) + "' has a non-integer count type");
        p.isList = true;
        p.countType = *countType;
        p.type = *itemType;
        p.name = std::string(w[4]);
        return p;
    }
    if (w.size() != 3) return makeError(name, "bad PLY header line: 'property' needs a type and a name");
    const auto type = scalarTypeFromName(w[1]);
    if (!type) return makeError(name, "unknown PLY property type " + quoteShort(w[1]));
    p.type = *type;
    p.name = std::string(w[2]);
    return p;
}

Result<Encoding> parseFormatLine(const std::vector<std::string_view>& w, const std::string& name) {
    if (w.size() < 2) return makeError(name, "bad PLY header: 'format' line names no format");
    if (w[1] == "ascii") return Encoding::Ascii;
    if (w[1] == "binary_little_endian") return Encoding::BinaryLittle;
    if (w[1] == "binary_big_endian") return Encoding::BinaryBig;
    return makeError(name, "unknown PLY format " + quoteShort(w[1]) +
                               " (expected ascii, binary_little_endian or binary_big_endian)");
}


}  // namespace

std::size_t sizeOf(ScalarType t) {
    switch (t) {
        case ScalarType::Int8:
        case ScalarType::UInt8: return 1;
        case ScalarType::Int16:
        case ScalarType::UInt16: return 2;
        case ScalarType::Int32:
        case ScalarType::UInt32:
        case ScalarType::Float32: return 4;
        case ScalarType::Float64: return 8;
    }
    return 1;
}

bool isIntegerType(ScalarType t) { return t != ScalarType::Float32 && t != ScalarType::Float64; }

int findScalar(const Element& e, std::string_view n) {
    for (std::size_t i = 0; i < e.properties.size(); ++i)
        if (!e.properties[i].isList && e.properties[i].name == n) return int(i);
    return -1;
}

Result<Header> parseHeader(std::string_view text, const std::string& name) {
    Header h;
    bool sawFormat = false;
    std::vector<std::string_view> w;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t nl = text.find('\n', pos);
        const std::size_t next = nl == std::string_view::npos ? text.size() : nl + 1;
        std::string_view line = text.substr(pos, (nl == std::string_view::npos ? text.size() : nl) - pos);
        pos = next;
        ++h.lineCount;
        splitWords(line, w);

        if (h.lineCount == 1) {
            if (w.size() != 1 || w[0] != "ply") return makeError(name, "not a PLY file: the first line is not 'ply'");
            continue;
        }
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (nl == std::string_view::npos && w[0] != "end_header") break;  // a cut-off last line
        if (w[0] == "end_header") {
            if (!sawFormat) return makeError(name, "bad PLY header: no 'format' line");
            h.bodyOffset = next;
            return h;
        }
        if (w[0] == "format") {
            auto enc = parseFormatLine(w, name);
            if (!enc) return enc.error();
            h.encoding = enc.value();
            h.formatName = std::string(w[1]);
            sawFormat = true;
        } else if (w[0] == "element") {
            Element e;
            if (w.size() != 3 || !parseCount(w[2], e.count))
                return makeError(name, "bad PLY header line " + quoteShort(line) + " (expected 'element NAME COUNT')");
            e.name = std::string(w[1]);
            h.elements.push_back(std::move(e));
        } else if (w[0] == "property") {
            if (h.elements.empty()) return makeError(name, "bad PLY header: 'property' line before any 'element' line");
            auto p = parsePropertyLine(w, name);
            if (!p) return p.error();
            h.elements.back().properties.push_back(std::move(p.value()));
        } else {
            return makeError(name, "bad PLY header line " + quoteShort(line));
        }
    }
    return makeError(name, "PLY header has no 'end_header' line (file truncated?)");
}

Status RowSource::skipElement(const Element& e) {
    if (e.properties.empty()) return okStatus();  // rows without properties hold no data
    std::vector<double> values;
    for (std::uint64_t r = 0; r < e.count; ++r) {
        Status s = readRow(e, r, values);
        if (!s) return s;
    }
    return okStatus();
}

namespace {

// ---------------------------------------------------------------- rows

class BinarySource final : public RowSource {
public:
    BinarySource(ByteView body, bool bigEndian, std::string formatName, const std::string& name)
        : body_(body), swap_(bigEndian != (std::endian::native == std::endian::big)),
          formatName_(std::move(formatName)), name_(name) {}

    using RowSource::readRow;
    Status readRow(const Element& e, std::uint64_t row, std::vector<double>& values, int keepList,
                   std::vector<double>* items) override {
        values.clear();
        if (items) items->clear();
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
            const Property& p = e.properties[i];
            double v = 0;
            if (!p.isList) {
                if (!read(p.type, v)) return truncated(e, row);
                values.push_back(v);
                continue;
            }
            if (!read(p.countType, v)) return truncated(e, row);
            if (v < 0) return makeError(name_, "negative list length in PLY element '" + e.name + "' " + std::to_string(row));
            const std::size_t item = sizeOf(p.type);
            if (v > double(remaining() / item)) return truncated(e, row);
            if (items && int(i) == keepList) {  // the bytes exist: checked just above
                for (std::size_t k = 0; k < std::size_t(v); ++k) {
                    double x = 0;
                    read(p.type, x);
                    items->push_back(x);
                }
            } else {
                pos_ += std::size_t(v) * item;
            }
        }
        return okStatus();
    }

    Status skipElement(const Element& e) override {
        const bool hasList = std::any_of(e.properties.begin(), e.properties.end(), [](const Property& p) { return p.isList; });
        if (hasList) return RowSource::skipElement(e);
        const std::size_t rowSize = fixedRowSize(e);
        if (rowSize == 0) return okStatus();
        if (e.count > remaining() / rowSize) return truncated(e, remaining() / rowSize);
        pos_ += std::size_t(e.count) * rowSize;
        return okStatus();
    }

    Status checkCount(const Element& e) override {
        const std::size_t rowSize = fixedRowSize(e);  // lists count their length field only
        if (rowSize == 0 || e.count <= remaining() / rowSize) return okStatus();
        return makeError(name_, "PLY element '" + e.name + "' declares " + std::to_string(e.count) + " rows of at least " +
                                    std::to_string(rowSize) + " bytes but only " + std::to_string(remaining()) +
                                    " bytes of data remain (file truncated or count wrong)" + asciiHint());
    }

private:
    std::size_t remaining() const { return body_.size() - pos_; }

    static std::size_t fixedRowSize(const Element& e) {
        std::size_t size = 0;
        for (const Property& p : e.properties) size += sizeOf(p.isList ? p.countType : p.type);
        return size;
    }

    bool read(ScalarType t, double& out) {
        const std::size_t n = sizeOf(t);
        if (remaining() < n) return false;
        std::uint8_t b[8];
        if (swap_)
            std::reverse_copy(body_.data() + pos_, body_.data() + pos_ + n, b);
        else
            std::memcpy(b, body_.data() + pos_, n);
        pos_ += n;
        out = decode(t, b);
        return true;
    }

    static double decode(ScalarType t, const std::uint8_t* b) {
        switch (t) {
            case ScalarType::Int8: return double(std::int8_t(b[0]));
            case ScalarType::UInt8: return double(b[0]);
            case ScalarType::Int16: return as<std::int16_t>(b);
            case ScalarType::UInt16: return as<std::uint16_t>(b);
            case ScalarType::Int32: return as<std::int32_t>(b);
            case ScalarType::UInt32: return as<std::uint32_t>(b);
            case ScalarType::Float32: return as<float>(b);
            case ScalarType::Float64: return as<double>(b);
        }
        return 0;
    }

    template <class T>
    static double as(const std::uint8_t* b) {
        T v;
        std::memcpy(&v, b, sizeof v);
        return double(v);
    }

    Status truncated(const Element& e, std::uint64_t row) const {
        return makeError(name_, "PLY data ends in element '" + e.name + "' row " + std::to_string(row) + " of " +
                                    std::to_string(e.count) + " (file truncated?)" + asciiHint());
    }

    // A common mistake: a text body under a binary format line.
    std::string asciiHint() const {
        const std::size_t n = std::min<std::size_t>(body_.size(), 256);
        if (n == 0) return "";
        for (std::size_t i = 0; i < n; ++i) {
            const char c = char(body_[i]);
            if (!(isSpace(c) || (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E'))
                return "";
        }
        return "; the data looks like ASCII text although the header says " + formatName_;
    }

    ByteView body_;
    std::size_t pos_ = 0;
    bool swap_;
    std::string formatName_;
    const std::string& name_;
};

class AsciiSource final : public RowSource {
public:
    AsciiSource(std::string_view body, std::size_t firstLine, const std::string& name)
        : text_(body), line_(firstLine), name_(name) {}

    using RowSource::readRow;
    Status readRow(const Element& e, std::uint64_t row, std::vector<double>& values, int keepList,
                   std::vector<double>* items) override {
        values.clear();
        if (items) items->clear();
        if (e.properties.empty()) return okStatus();  // such rows hold nothing
        if (!nextLine())
            return makeError(name_, "PLY data ends after " + std::to_string(row) + " of " + std::to_string(e.count) +
                                        " '" + e.name + "' rows (too few values)");
        std::size_t k = 0;  // next word
        for (std::size_t i = 0; i < e.properties.size(); ++i) {
            const Property& p = e.properties[i];
            if (!p.isList) {
                double v = 0;
                Status s = number(e, p, k++, p.type, v);
                if (!s) return s;
                values.push_back(v);
                continue;
            }
            double n = 0;
            Status s = number(e, p, k++, p.countType, n);
            if (!s) return s;
            if (n < 0) return lineError("negative list length for property '" + p.name + "'");
            if (n > double(words_.size() - k)) return tooFew(e);
            for (std::size_t end = k + std::size_t(n); k < end; ++k) {
                double item = 0;
                Status si = number(e, p, k, p.type, item);
                if (!si) return si;
                if (items && int(i) == keepList) items->push_back(item);
            }
        }
        if (k != words_.size())
            return lineError("expected " + std::to_string(k) + " values for a '" + e.name + "' row, found " +
                             std::to_string(words_.size()));
        return okStatus();
    }

    Status checkCount(const Element& e) override {
        // Each non-empty row takes at least one character and a line break.
        if (e.properties.empty() || e.count <= (text_.size() - pos_ + 1) / 2) return okStatus();
        return makeError(name_, "PLY element '" + e.name + "' declares " + std::to_string(e.count) +
                                    " rows but only " + std::to_string(text_.size() - pos_) +
                                    " bytes of data remain (too few values)");
    }

private:
    // Advances to the next non-blank line and splits it into words_.
    bool nextLine() {
        while (pos_ < text_.size()) {
            const std::size_t nl = text_.find('\n', pos_);
            const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
            const std::string_view line = text_.substr(pos_, end - pos_);
            pos_ = nl == std::string_view::npos ? text_.size() : nl + 1;
            ++line_;
            splitWords(line, words_);
            if (!words_.empty()) return true;
        }
        return false;
    }

    Status number(const Element& e, const Property& p, std::size_t k, ScalarType type, double& out) {
        if (k >= words_.size()) return tooFew(e);
        if (!parseNumber(words_[k], out))
            return lineError(quoteShort(words_[k]) + " is not a number (property '" + p.name + "')");
        if (isIntegerType(type) && !(std::isfinite(out) && out == std::trunc(out)))
            return lineError(quoteShort(words_[k]) + " is not an integer (property '" + p.name + "')");
        return okStatus();
    }

    Status tooFew(const Element& e) const { return lineError("too few values for a '" + e.name + "' row"); }

    Status lineError(const std::string& what) const {
        return makeError(name_, "line " + std::to_string(line_) + ": " + what);
    }

    std::string_view text_;
    std::size_t pos_ = 0;
    std::size_t line_;  // number of the current line (1-based, whole file)
    std::vector<std::string_view> words_;
    const std::string& name_;
};


}  // namespace

std::unique_ptr<RowSource> makeRowSource(const Header& h, ByteView data, const std::string& name) {
    const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
    if (h.encoding == Encoding::Ascii)
        return std::make_unique<AsciiSource>(text.substr(h.bodyOffset), h.lineCount, name);
    return std::make_unique<BinarySource>(data.subspan(h.bodyOffset), h.encoding == Encoding::BinaryBig,
                                          h.formatName, name);
}

}  // namespace meniscus::ply
