// `meniscus convert IN OUT` (convert.h). Each frame is read as every command
// reads it (the alias table names its attributes: DualSPHysics' Idp becomes
// id, PySPH's u v w velocity) and written by writeParticles under names every
// reader maps back, so a round trip keeps positions bit for bit and every
// attribute. Nothing is derived: no radius from h, no up-axis turn.
#include "convert.h"

#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>

#include "common.h"
#include "help_format.h"
#include "interrupt.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "progress.h"

namespace meniscus::app {

namespace {

bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b) {
    std::error_code ec;
    return std::filesystem::exists(b, ec) && std::filesystem::equivalent(a, b, ec);
}

}  // namespace

CLI::App* addConvertCommand(CLI::App& app, ConvertOptions& o) {
    auto* cmd = app.add_subcommand(
        "convert",
        "Convert particle files between formats, every attribute kept: read any format Meniscus reads (BGEO, VTK, "
        "VTU/VTP, PLY, CSV incl. DualSPHysics, XYZ, H5Part, PySPH .hdf5/.npz), write BGEO (.bgeo, .bgeo.gz), legacy "
        "VTK (.vtk), VTK XML (.vtu, .vtp) or PLY (.ply), chosen by OUTPUT's extension. Positions are kept bit for "
        "bit (as 32-bit floats); attribute names are the canonical ones (velocity, density, id) and the file's own "
        "for the rest");
    cmd->add_option("input", o.input,
                    "Particle file, directory, pattern (frame_%04d.bgeo, data_*.vtk) or collection (.pvd, .h5part)")
        ->group(group::kInput)
        ->required();
    cmd->add_option("output", o.output,
                    "Output file; for a sequence a printf pattern (out_%04d.vtu), filled with each input frame's own "
                    "number")
        ->group(group::kOutput)
        ->required();
    cmd->add_option("--pvd", o.pvd,
                    "Also write a ParaView collection (.pvd) listing the outputs, for opening the series in "
                    "ParaView as one: each output's time is its input's time when the input is a .pvd, else its "
                    "frame number")
        ->group(group::kOutput);
    addSelectOption(cmd, o.select);
    addRow(cmd, *findIn(meshOptionTable(), "resume"), &o.resume);  // one --resume for mesh and convert
    useGroupedHelp(cmd, {group::kInput, group::kOutput});
    return cmd;
}

int runConvert(const ConvertOptions& o) {
    auto format = writableFormatOf(o.output);
    if (!format) return fail(format.error());
    auto filter = parseSelection(o.select);
    if (!filter) return fail(filter.error());
    auto files = expandSequence(o.input);
    if (!files) return fail(files.error());
    Frames frames;
    frames.files = std::move(*files);
    if (auto st = frames.checkOutput(o.output, "out_%04d.vtu"); !st) return fail(st.error());

    if (!o.pvd.empty() && !isPvdName(o.pvd)) return fail(o.pvd + ": --pvd must end in .pvd");
    // The times a .pvd collection gives its frames; else each frame's number (its position when it has none).
    std::vector<double> times;
    if (isPvdName(o.input)) {
        auto pvd = readPvd(o.input);
        if (!pvd) return fail(pvd.error());
        times = pvd->times;
    }
    for (std::size_t i = times.size(); i < frames.count(); ++i) {
        const long n = frameNumberOf(frames.files[i]);
        times.push_back(n >= 0 ? double(n) : double(i));
    }
    std::vector<std::filesystem::path> written;
    if (frames.count() > 0) {
        auto first = frames.outputName(o.output, 0);
        if (!first) return fail(first.error());
        if (auto st = prepareOutputFolder(*first); !st) return fail(st.error());
    }
    installInterruptHandler("frame");  // from here on Ctrl-C stops after the frame in progress

    ProgressBar progress(frames.count(), "converting");
    for (std::size_t i = 0; i < frames.count(); ++i) {
        if (interrupted())
            return stopInterrupted(i ? "after frame " + std::to_string(i) + " of " + std::to_string(frames.count())
                                     : "before the first frame",
                                   "the files written are whole: the same command with --resume writes the rest" +
                                       std::string(o.pvd.empty() ? "" : " and the .pvd"));
        const std::filesystem::path& in = frames.files[i];
        auto out = frames.outputName(o.output, i);
        if (!out) return fail(out.error());
        if (sameFile(in, *out)) return fail(*out + ": is the input " + in.string() + "; give another output name");
        if (o.resume && particlesComplete(*out)) {  // written whole by the interrupted run
            progress.step(i + 1, *out + " (complete, kept)");
            written.push_back(*out);
            continue;
        }
        if (auto st = makeOutputFolders(*out); !st) return fail(st.error());
        // A frame with no particles (a simulation before its emitter started) is written as an empty file.
        auto set = readParticles(in, ParticleFormat::Auto, true);
        if (!set) return fail(set.error());
        printWarnings(*set);
        if (set->size() > 0)
            if (auto st = applySelection(*set, *filter, in.string()); !st) return fail(st.error());
        if (auto st = writeParticles(*out, *set, *format); !st) return fail(st.error());
        progress.step(i + 1, *out + " (" + std::to_string(set->size()) + " particles)");
        written.push_back(*out);
    }
    if (!o.pvd.empty()) {
        times.resize(written.size());
        if (auto st = makeOutputFolders(o.pvd); !st) return fail(st.error());
        if (auto st = writePvd(o.pvd, written, times); !st) return fail(st.error());
    }
    return 0;
}

}  // namespace meniscus::app
