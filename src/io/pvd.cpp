// ParaView data collections (.pvd): the time series index ParaView writes
// ("Save Data" of a series; its vtkPVDReader reads it) and simulation codes
// write beside their .vtu/.vtp frames:
//
//   <VTKFile type="Collection" version="0.1" ...>
//     <Collection>
//       <DataSet timestep="0.1" group="" part="0" file="frames/f_0001.vtu"/>
//       ...
//
// Rules (see io.h):
//  - every DataSet needs a non-empty `file`; a relative one is relative to the
//    .pvd's folder;
//  - `timestep` is a finite number; either every DataSet has one or none does
//    (then the file order counts, as times 0, 1, 2, ...);
//  - `part` (default 0) splits a timestep into pieces written as separate
//    files; one file per timestep is read: the one with the lowest part
//    (part 0 as ParaView writes it), the others are counted in `warnings`;
//  - the frames come in ascending timestep order (equal timesteps of
//    different parts: the lowest part; two files for one timestep and part are
//    an error), whatever their order in the file.
// Problems come back as an Error naming the .pvd, never as a crash.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include <tinyxml2.h>

#include "io/atomic_file.h"
#include "io/containers.h"
#include "io/io_util.h"
#include "meniscus/io.h"

namespace meniscus {

namespace fs = std::filesystem;

namespace {

using io_util::fail;

std::string trimmed(const char* s) {
    std::string_view v(s ? s : "");
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t' || v.front() == '\n' || v.front() == '\r'))
        v.remove_prefix(1);
    while (!v.empty() && (v.back() == ' ' || v.back() == '\t' || v.back() == '\n' || v.back() == '\r'))
        v.remove_suffix(1);
    return std::string(v);
}

std::string timeText(double t) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", t);
    return buf;
}

struct Entry {
    double time = 0.0;
    long long part = 0;
    std::size_t index = 0;  // position in the file, from 0
    std::string file;
};

PvdCollection parsePvdDocument(ByteView data, const fs::path& baseDir) {
    if (data.empty()) fail("file is empty");
    tinyxml2::XMLDocument doc;
    if (doc.Parse(reinterpret_cast<const char*>(data.data()), data.size()) != tinyxml2::XML_SUCCESS)
        fail(std::string("malformed or truncated XML: ") + (doc.ErrorStr() ? doc.ErrorStr() : "unknown error"));
    const tinyxml2::XMLElement* root = doc.RootElement();
    if (!root) fail("not a ParaView collection (no XML element)");
    if (std::string_view(root->Name()) != "VTKFile")
        fail("not a ParaView collection (root element is <" + std::string(root->Name()) + ">, expected <VTKFile>)");
    const char* type = root->Attribute("type");
    if (!type || std::string_view(type) != "Collection")
        fail("not a ParaView collection (VTKFile type " + io_util::quoteShort(type ? type : "(none)") +
             ", expected 'Collection')");
    const tinyxml2::XMLElement* collection = root->FirstChildElement("Collection");
    if (!collection) fail("missing <Collection> element");

    std::vector<Entry> entries;
    std::size_t withTime = 0;
    for (const auto* e = collection->FirstChildElement("DataSet"); e; e = e->NextSiblingElement("DataSet")) {
        Entry d;
        d.index = entries.size();
        const std::string what = "DataSet " + std::to_string(d.index + 1);
        const char* file = e->Attribute("file");
        if (!file || trimmed(file).empty()) fail(what + " has no file attribute");
        d.file = file;
        if (const char* t = e->Attribute("timestep")) {
            const std::string text = trimmed(t);
            if (!io_util::parseNumber(text, d.time) || !std::isfinite(d.time))
                fail(what + ": bad timestep " + io_util::quoteShort(t) + " (expected a finite number)");
            ++withTime;
        }
        if (const char* p = e->Attribute("part")) {
            const std::string text = trimmed(p);
            double v = 0.0;
            if (!io_util::parseNumber(text, v) || v != std::floor(v) || v < 0.0 || v > 1e15)
                fail(what + ": bad part " + io_util::quoteShort(p) + " (expected a whole number from 0)");
            d.part = (long long)v;
        }
        entries.push_back(std::move(d));
    }
    if (entries.empty()) fail("no datasets (the <Collection> holds no <DataSet> elements)");
    if (withTime != 0 && withTime != entries.size())
        fail(std::to_string(entries.size() - withTime) + " of " + std::to_string(entries.size()) +
             " DataSet elements have no timestep (give every one a timestep, or none)");
    if (withTime == 0)
        for (Entry& d : entries) d.time = double(d.index);

    // Ascending time, then part, then file order.
    std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        if (a.time != b.time) return a.time < b.time;
        return a.part < b.part;
    });
    PvdCollection out;
    out.timed = withTime != 0;
    std::size_t otherParts = 0;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const Entry& d = entries[i];
        if (i > 0 && entries[i - 1].time == d.time) {
            if (entries[i - 1].part == d.part)
                fail("DataSet " + std::to_string(entries[i - 1].index + 1) + " and " + std::to_string(d.index + 1) +
                     " are both timestep " + timeText(d.time) + ", part " +
                     std::to_string(d.part));
            ++otherParts;
            continue;
        }
        const fs::path file(d.file);
        out.files.push_back(file.is_absolute() || baseDir.empty() ? file : baseDir / file);
        out.times.push_back(d.time);
        out.parts.push_back(d.part);
    }
    if (otherParts)
        out.warnings.push_back(std::to_string(otherParts) +
                               " dataset(s) of further parts left out (one file per timestep: its lowest part)");
    return out;
}

}  // namespace

bool isPvdName(std::string_view name) { return io_util::endsWith(io_util::lower(name), ".pvd"); }

Result<PvdCollection> parsePvd(ByteView data, const std::string& name, const fs::path& baseDir) {
    try {
        return parsePvdDocument(data, baseDir);
    } catch (const io_util::ParseFailure& f) {
        return makeError(name, f.message);
    } catch (const std::bad_alloc&) {
        return makeError(name, "out of memory reading a ParaView collection");
    } catch (const std::exception& e) {
        return makeError(name, std::string("cannot read ParaView collection: ") + e.what());
    }
}

Result<PvdCollection> readPvd(const fs::path& path) {
    // An index of file names: small, and XML from its first byte.
    auto bytes = io_util::readFileChecked(path, io_util::kMaxPvdFileBytes, [&](ByteView head) -> Status {
        std::size_t i = head.size() >= 3 && head[0] == 0xEF && head[1] == 0xBB && head[2] == 0xBF ? 3 : 0;
        while (i < head.size() && (head[i] == ' ' || head[i] == '\t' || head[i] == '\r' || head[i] == '\n')) ++i;
        if (head.empty() || (i < head.size() && head[i] == '<')) return okStatus();
        return makeError(path.string(), "not a ParaView collection (not XML: the file does not start with '<')");
    });
    if (!bytes) return bytes.error();
    auto pvd = parsePvd(ByteView(bytes->data(), bytes->size()), path.string(), path.parent_path());
    if (!pvd) return pvd;
    for (std::size_t i = 0; i < pvd->files.size(); ++i) {
        std::error_code ec;
        const fs::path& f = pvd->files[i];
        if (!fs::is_regular_file(f, ec))
            return makeError(path.string(), "the file of timestep " + timeText(pvd->times[i]) +
                                                 ", '" + f.string() + "', " +
                                                 (fs::exists(f, ec) ? "is not a regular file" : "does not exist"));
    }
    return pvd;
}

std::optional<double> evenFrameRate(std::span<const double> times) {
    if (times.size() < 2) return std::nullopt;
    const double mean = (times.back() - times.front()) / double(times.size() - 1);
    if (!(mean > 0.0) || !std::isfinite(mean)) return std::nullopt;
    for (std::size_t i = 1; i < times.size(); ++i)
        if (std::abs(times[i] - times[i - 1] - mean) > 1e-3 * mean) return std::nullopt;
    return 1.0 / mean;
}

Result<std::optional<double>> frameRateOfInput(const fs::path& input) {
    std::error_code ec;
    if (!fs::is_regular_file(input, ec)) return std::optional<double>();
    if (io_util::isHdf5Name(input.filename().string())) {
        auto times = h5partStepTimes(input);
        if (!times) return times.error();
        return evenFrameRate(*times);
    }
    if (!isPvdName(input.filename().string())) return std::optional<double>();
    auto pvd = readPvd(input);
    if (!pvd) return pvd.error();
    if (!pvd->timed) return std::optional<double>();
    return evenFrameRate(pvd->times);
}

Status writePvd(const fs::path& path, const std::vector<fs::path>& files, const std::vector<double>& times) {
    const std::string name = path.string();
    if (files.size() != times.size())
        return makeError(name, std::to_string(files.size()) + " files but " + std::to_string(times.size()) + " times");
    for (double t : times)
        if (!std::isfinite(t)) return makeError(name, "a timestep that is not a finite number");
    tinyxml2::XMLDocument doc;
    doc.InsertEndChild(doc.NewDeclaration());
    tinyxml2::XMLElement* root = doc.NewElement("VTKFile");
    root->SetAttribute("type", "Collection");
    root->SetAttribute("version", "0.1");
    root->SetAttribute("byte_order", "LittleEndian");
    doc.InsertEndChild(root);
    tinyxml2::XMLElement* collection = root->InsertNewChildElement("Collection");
    const fs::path base = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    for (std::size_t i = 0; i < files.size(); ++i) {
        // Relative to the .pvd, so the folder can move as a whole.
        std::error_code ec;
        fs::path rel = fs::relative(files[i], base, ec);
        if (ec || rel.empty()) rel = files[i];
        char time[32];
        std::snprintf(time, sizeof time, "%.17g", times[i]);
        tinyxml2::XMLElement* ds = collection->InsertNewChildElement("DataSet");
        ds->SetAttribute("timestep", time);
        ds->SetAttribute("group", "");
        ds->SetAttribute("part", 0);
        ds->SetAttribute("file", rel.generic_string().c_str());
    }
    tinyxml2::XMLPrinter printer;
    doc.Print(&printer);
    return writeAtomically(path, [&](const fs::path& tmp) -> Status {
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) return makeError(name, "cannot open for writing");
        const std::size_t size = std::size_t(printer.CStrSize() - 1);  // without the terminating NUL
        const bool ok = std::fwrite(printer.CStr(), 1, size, f) == size;
        if (std::fclose(f) != 0 || !ok) return makeError(name, "write error");
        return okStatus();
    });
}

}  // namespace meniscus
