// Frame sequences: expanding an input spec (file, directory, printf pattern or
// glob) into an ordered list of particle files, natural ordering of names, and
// output names from printf patterns.
//
// Rules (see io.h):
//  - An existing regular file is a sequence of one, whatever its name holds,
//    except a ParaView collection (*.pvd): the files it lists, in timestep
//    order (readPvd, src/io/pvd.cpp); and an H5Part file: its steps, as paths
//    into it (run.h5part/Step#0, ...), in step order (listH5PartSteps).
//  - A path into a container (run.h5part/Step#3, out.hdf5/fluid) is itself;
//    a pattern or glob of containers followed by a path into each
//    (out_*.hdf5/fluid) is the pattern's files, each with that path.
//  - A directory gives every regular particle file in it (.bgeo, .bgeo.gz, .vtk,
//    .vtu, .vtp, .ply, .csv, .xyz, .h5part, .h5, .hdf5, .npz; case-insensitive). When it holds several
//    kinds, the most numerous extension wins (ties: the order of that list),
//    silently: a simulation directory often holds a few stray exports besides
//    the frames.
//  - A printf pattern has exactly one integer conversion in its file name: %d,
//    %Nd (space padded) or %0Nd (zero padded); %% is a literal '%'. A file fits
//    when its name is the text around the conversion with a digit run in
//    between that is at least as long as the padding width (frame_%04d.ply
//    fits frame_0001.ply and frame_12345.ply, not frame_1.ply); for %Nd the run
//    may also be space padded to exactly N characters, as printf writes it.
//  - A glob has '*' and/or '?' in its file name (not in its directories);
//    matched with fnmatch(3), other characters literal.
// In every case hidden files (leading '.') and temporary/backup files (names
// ending in ~, .tmp, .temp, .part, .swp) are ignored, and the frames are sorted
// with naturalLess on their file names; an H5Part file among them then gives
// its steps in its place.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <map>
#include <optional>

#include <fnmatch.h>

#include "io/containers.h"
#include "io/io_util.h"
#include "meniscus/io.h"

namespace meniscus {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kParticleExtensions[] = {".bgeo.gz", ".bgeo", ".vtk", ".vtu",  ".vtp", ".ply",
                                                    ".csv",     ".xyz",  ".h5part", ".h5", ".hdf5", ".npz"};
// Preference when two extensions are equally numerous in a directory.
constexpr std::string_view kExtensionPreference[] = {".bgeo", ".bgeo.gz", ".vtk",    ".vtu", ".vtp", ".ply",
                                                     ".csv",  ".xyz",     ".h5part", ".h5",  ".hdf5", ".npz"};

bool isDigit(char c) { return c >= '0' && c <= '9'; }

using io_util::endsWith;
using io_util::lower;

// The particle extension of a file name ("" when none), longest match first.
std::string_view particleExtension(std::string_view fileName) {
    const std::string n = lower(fileName);
    for (std::string_view ext : kParticleExtensions)
        if (n.size() > ext.size() && endsWith(n, ext)) return ext;
    return {};
}

bool isIgnoredName(std::string_view fileName) {
    if (fileName.empty() || fileName.front() == '.') return true;
    const std::string n = lower(fileName);
    for (std::string_view suffix : {"~", ".tmp", ".temp", ".part", ".swp"})
        if (endsWith(n, suffix)) return true;
    return false;
}

// Names of the regular files (symlinks to files included) in `dir` that are not
// hidden or temporary.
Result<std::vector<std::string>> listFiles(const fs::path& dir, const std::string& spec) {
    std::error_code ec;
    const fs::path where = dir.empty() ? fs::path(".") : dir;
    if (!fs::is_directory(where, ec))
        return makeError(spec, "directory '" + where.string() + "' does not exist");
    std::vector<std::string> names;
    fs::directory_iterator it(where, ec), end;
    if (ec) return makeError(spec, "cannot list directory '" + where.string() + "': " + ec.message());
    for (; it != end; it.increment(ec)) {
        if (ec) return makeError(spec, "cannot list directory '" + where.string() + "': " + ec.message());
        std::error_code typeEc;
        if (!it->is_regular_file(typeEc)) continue;
        std::string n = it->path().filename().string();
        if (!isIgnoredName(n)) names.push_back(std::move(n));
    }
    return names;
}

void sortNatural(std::vector<std::string>& names) {
    std::sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) { return naturalLess(a, b); });
}

std::vector<fs::path> joinAll(const fs::path& dir, const std::vector<std::string>& names) {
    std::vector<fs::path> out;
    out.reserve(names.size());
    for (const std::string& n : names) out.push_back(dir.empty() ? fs::path(n) : dir / n);
    return out;
}

// ---------------------------------------------------------------- printf patterns

struct FramePattern {
    std::string prefix;  // literal text before the conversion (%% unescaped)
    std::string suffix;  // literal text after it
    bool zeroPad = false;
    int width = 0;       // 0: no padding
};

// Parses a pattern with exactly one %d / %Nd / %0Nd. On failure returns the
// reason (without the pattern itself).
Result<FramePattern> parseFramePattern(std::string_view pattern) {
    FramePattern fp;
    int conversions = 0;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        std::string& text = conversions == 0 ? fp.prefix : fp.suffix;
        if (pattern[i] != '%') {
            text += pattern[i];
            continue;
        }
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            text += '%';
            ++i;
            continue;
        }
        // %[0][width]d
        std::size_t j = i + 1;
        bool zero = false;
        if (j < pattern.size() && pattern[j] == '0') {
            zero = true;
            ++j;
        }
        int width = 0;
        while (j < pattern.size() && isDigit(pattern[j])) {
            width = width * 10 + (pattern[j] - '0');
            if (width > 64) return makeError("", "padding width is larger than 64");
            ++j;
        }
        if (j >= pattern.size() || pattern[j] != 'd') {
            std::string what(pattern.substr(i, std::min(j + 1, pattern.size()) - i));
            what.insert(0, 1, '\'');
            what += "' is not a supported conversion (use %d, %4d or %04d; %% for a literal %)";
            return makeError("", what);
        }
        if (++conversions > 1) return makeError("", "it has more than one %d conversion");
        fp.zeroPad = zero && width > 0;
        fp.width = width;
        i = j;
    }
    if (conversions == 0) return makeError("", "it has no %d conversion for the frame number");
    return fp;
}

// True when `middle` is what the conversion could print for some number.
bool fitsConversion(std::string_view middle, const FramePattern& fp) {
    std::size_t spaces = 0;
    if (!fp.zeroPad)
        while (spaces < middle.size() && middle[spaces] == ' ') ++spaces;
    const std::string_view digits = middle.substr(spaces);
    if (digits.empty() || !std::all_of(digits.begin(), digits.end(), isDigit)) return false;
    if (spaces > 0) return middle.size() == std::size_t(fp.width);  // space padding fills the width exactly
    return digits.size() >= std::size_t(fp.width);
}

bool fitsPattern(std::string_view name, const FramePattern& fp) {
    if (name.size() < fp.prefix.size() + fp.suffix.size() + 1) return false;
    if (name.substr(0, fp.prefix.size()) != fp.prefix || !endsWith(name, fp.suffix)) return false;
    return fitsConversion(name.substr(fp.prefix.size(), name.size() - fp.prefix.size() - fp.suffix.size()), fp);
}

// ---------------------------------------------------------------- spec kinds

// The spec split into directory and file-name parts.
struct SplitSpec {
    fs::path dir;
    std::string file;
};

SplitSpec splitSpec(const std::string& spec) {
    const fs::path p(spec);
    return {p.parent_path(), p.filename().string()};
}

// A '%' that is not half of "%%".
bool hasConversion(std::string_view s) {
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '%') continue;
        if (i + 1 < s.size() && s[i + 1] == '%') {
            ++i;
            continue;
        }
        return true;
    }
    return false;
}

bool hasWildcard(std::string_view s) { return s.find_first_of("*?") != std::string_view::npos; }

Result<std::vector<fs::path>> expandDirectory(const std::string& spec) {
    const fs::path dir(spec);
    auto names = listFiles(dir, spec);
    if (!names) return names.error();
    std::map<std::string_view, std::vector<std::string>> byExtension;
    for (std::string& n : names.value()) {
        const std::string_view ext = particleExtension(n);
        if (!ext.empty()) byExtension[ext].push_back(std::move(n));
    }
    const std::vector<std::string>* best = nullptr;
    for (std::string_view ext : kExtensionPreference) {
        auto it = byExtension.find(ext);
        if (it != byExtension.end() && (!best || it->second.size() > best->size())) best = &it->second;
    }
    if (!best)
        return makeError(spec, "directory holds no particle files (.bgeo, .bgeo.gz, .vtk, .vtu, .vtp, .ply, .csv, .xyz, "
                               ".h5part, .h5, .hdf5, .npz)");
    std::vector<std::string> chosen = *best;
    sortNatural(chosen);
    return joinAll(dir, chosen);
}

Result<std::vector<fs::path>> expandPrintf(const std::string& spec) {
    const SplitSpec s = splitSpec(spec);
    if (hasConversion(s.dir.string()))
        return makeError(spec, "a %d frame-number pattern may only be in the file name, not in its directories");
    if (hasWildcard(s.file)) return makeError(spec, "a pattern cannot mix %d with the wildcards * and ?");
    auto fp = parseFramePattern(s.file);
    if (!fp) return makeError(spec, "not a usable frame-number pattern: " + fp.error().message);
    auto names = listFiles(s.dir, spec);
    if (!names) return names.error();
    std::vector<std::string> matched;
    for (const std::string& n : names.value())
        if (fitsPattern(n, fp.value())) matched.push_back(n);
    if (matched.empty()) return makeError(spec, "no files match this frame-number pattern");
    sortNatural(matched);
    return joinAll(s.dir, matched);
}

// Only '*' and '?' are wildcards: '[' and '\' are escaped for fnmatch.
std::string globForFnmatch(std::string_view file) {
    std::string out;
    for (char c : file) {
        if (c == '[') out += "[[]";
        else if (c == '\\') out += "\\\\";
        else out += c;
    }
    return out;
}

Result<std::vector<fs::path>> expandGlob(const std::string& spec) {
    const SplitSpec s = splitSpec(spec);
    if (hasWildcard(s.dir.string()))
        return makeError(spec, "wildcards (* and ?) may only be in the file name, not in its directories");
    const std::string glob = globForFnmatch(s.file);
    auto names = listFiles(s.dir, spec);
    if (!names) return names.error();
    std::vector<std::string> matched;
    for (const std::string& n : names.value())
        if (::fnmatch(glob.c_str(), n.c_str(), FNM_PERIOD) == 0) matched.push_back(n);
    if (matched.empty()) return makeError(spec, "no files match this pattern");
    sortNatural(matched);
    return joinAll(s.dir, matched);
}

// The steps of an H5Part file as paths into it; nullopt when `file` is not
// an HDF5-named file with H5Part steps (or cannot be read: reading it later
// says why).
std::optional<std::vector<fs::path>> h5partFrames(const fs::path& file) {
    if (!io_util::isHdf5Name(file.filename().string())) return std::nullopt;
    auto steps = listH5PartSteps(file);
    if (!steps || steps->empty()) return std::nullopt;
    std::vector<fs::path> out;
    for (const std::string& s : *steps) out.push_back(file / s);
    return out;
}

// Each H5Part file of a listing replaced by its steps.
std::vector<fs::path> withH5PartSteps(std::vector<fs::path> files) {
    std::vector<fs::path> out;
    for (fs::path& f : files) {
        if (auto steps = h5partFrames(f)) out.insert(out.end(), steps->begin(), steps->end());
        else out.push_back(std::move(f));
    }
    return out;
}

// A pattern of containers with a path into each: "out_*.hdf5/fluid" splits
// into the pattern "out_*.hdf5" and "fluid"; nullopt when `spec` has no such
// part (the first part from the left named like a container with a pattern).
std::optional<std::pair<std::string, std::string>> splitContainerPattern(const std::string& spec) {
    const fs::path p(spec);
    fs::path head;
    fs::path tail;
    bool found = false;
    for (const fs::path& part : p) {
        if (found) {
            tail /= part;
            continue;
        }
        head /= part;
        const std::string name = part.string();
        if (io_util::isContainerName(name) && (hasConversion(name) || hasWildcard(name))) found = true;
    }
    if (!found || tail.empty()) return std::nullopt;
    return std::make_pair(head.string(), tail.string());
}

Result<std::vector<fs::path>> expandSequenceImpl(const std::string& spec) {
    if (spec.empty()) return makeError("", "empty input path");
    std::error_code ec;
    const fs::path p(spec);
    if (fs::is_regular_file(p, ec)) {
        if (isPvdName(p.filename().string())) {
            auto pvd = readPvd(p);
            if (!pvd) return pvd.error();
            return std::move(pvd->files);
        }
        if (auto steps = h5partFrames(p)) return std::move(*steps);
        return std::vector<fs::path>{p};
    }
    if (fs::is_directory(p, ec)) {
        auto files = expandDirectory(spec);
        if (!files) return files;
        return withH5PartSteps(std::move(*files));
    }
    // A frame inside a container (run.h5part/Step#3, out.hdf5/fluid).
    if (io_util::splitContainerPath(p)) return std::vector<fs::path>{p};
    if (auto split = splitContainerPattern(spec)) {
        auto files = expandSequenceImpl(split->first);
        if (!files) return makeError(spec, files.error().message);
        for (fs::path& f : *files) f /= split->second;
        return files;
    }
    const std::string file = splitSpec(spec).file;
    if (hasConversion(file) || hasWildcard(file)) {
        auto files = hasConversion(file) ? expandPrintf(spec) : expandGlob(spec);
        if (!files) return files;
        return withH5PartSteps(std::move(*files));
    }
    if (hasConversion(spec) || hasWildcard(spec))
        return makeError(spec, "patterns (%d, * and ?) may only be in the file name, not in its directories");
    if (fs::exists(p, ec)) return makeError(spec, "not a regular file or directory");
    return makeError(spec, "no such file or directory");
}

}  // namespace

Result<std::vector<fs::path>> expandSequence(const std::string& spec) {
    try {
        return expandSequenceImpl(spec);
    } catch (const std::exception& e) {
        return makeError(spec, std::string("cannot expand input: ") + e.what());
    }
}

bool isSequenceSpec(const std::string& spec) {
    std::error_code ec;
    const fs::path p(spec);
    if (spec.empty()) return false;
    if (fs::is_regular_file(p, ec)) {
        if (isPvdName(p.filename().string())) return true;
        const auto steps = h5partFrames(p);
        return steps && steps->size() > 1;
    }
    if (splitContainerPattern(spec)) return true;
    if (fs::is_directory(p, ec)) return true;
    const std::string file = splitSpec(spec).file;
    return hasConversion(file) || hasWildcard(file);
}

// Digit runs compare by numeric value, everything else bytewise. When two names
// differ only in the zero padding of their numbers, the first run whose padding
// differs decides: less padding first ("a_2" < "a_02"). This is a strict total
// order on distinct strings, as std::sort needs.
bool naturalLess(std::string_view a, std::string_view b) {
    std::size_t i = 0, j = 0;
    int paddingOrder = 0;  // <0: a has less padding at the first difference
    while (i < a.size() && j < b.size()) {
        if (!isDigit(a[i]) || !isDigit(b[j])) {
            if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
            ++i;
            ++j;
            continue;
        }
        // Both at a digit run: skip leading zeros, then compare by length and digits.
        const std::size_t ai = i, bj = j;
        while (i < a.size() && a[i] == '0') ++i;
        while (j < b.size() && b[j] == '0') ++j;
        const std::size_t aZeros = i - ai, bZeros = j - bj;
        const std::size_t as = i, bs = j;
        while (i < a.size() && isDigit(a[i])) ++i;
        while (j < b.size() && isDigit(b[j])) ++j;
        const std::string_view av = a.substr(as, i - as), bv = b.substr(bs, j - bs);
        if (av.size() != bv.size()) return av.size() < bv.size();
        if (av != bv) return av < bv;
        if (paddingOrder == 0 && aZeros != bZeros) paddingOrder = aZeros < bZeros ? -1 : 1;
    }
    const bool aDone = i == a.size(), bDone = j == b.size();
    if (aDone != bDone) return aDone;  // a prefix sorts first
    return paddingOrder < 0;
}

Result<std::string> formatFramePattern(const std::string& pattern, long number) {
    auto fp = parseFramePattern(pattern);
    if (!fp) return makeError("", "output pattern '" + pattern + "' is not usable: " + fp.error().message);
    char spec[16];
    std::snprintf(spec, sizeof spec, fp->zeroPad ? "%%0%dld" : "%%%dld", fp->width);
    char digits[96];
    std::snprintf(digits, sizeof digits, spec, number);
    return fp->prefix + digits + fp->suffix;
}

}  // namespace meniscus
