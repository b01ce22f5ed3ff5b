#include "mesh.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>
#include <iostream>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "common.h"
#include "help_format.h"
#include "interrupt.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/surface.h"
#include "progress.h"

namespace meniscus::app {

CLI::App* addMeshCommand(CLI::App& app, MeshJob& o) {
    auto* cmd = app.add_subcommand(
        "mesh",
        "Extract the liquid's surface as a closed triangle mesh (binary PLY, OBJ, or VTK .vtp/.vtk with a .pvd "
        "for a sequence; vertex normals, and attributes with --interpolate) for Blender, Houdini or ParaView: block-parallel surface-following marching cubes (thesis §4.2, Rosenberg & "
        "Birdwell 2008). The same mesh for any --threads");
    cmd->add_option("input", o.input, "Particle file, directory, or pattern (frame_%04d.ply, data_*.bgeo)")
        ->group(group::kInput)
        ->required();
    cmd->add_option("-o,--output", o.output,
                    "Output .ply (binary, default), .obj, .vtp or .vtk; for a sequence a pattern like mesh_%04d.ply "
                    "(VTK: and a .pvd of the sequence beside, m_%04d.vtp -> m.pvd)")
        ->group(group::kOutput)
        ->required();
    addRows(cmd, meshOptionTable(), o);  // --radius under Input, --stats and --resume under Output
    addSmoothingLengthOption(cmd, o.hPerSpacing);
    addSelectOption(cmd, o.select);
    addMesherTableOptions(cmd, o.mesher);
    useGroupedHelp(cmd, {group::kInput, group::kSurface, group::kOutput, group::kPerformance});
    return cmd;
}

namespace {

// --interpolate's names: each value a name or a comma-separated list.
std::vector<std::string> interpolatedNames(const std::vector<std::string>& values) {
    std::vector<std::string> names;
    for (const std::string& v : values) {
        std::size_t start = 0;
        while (start <= v.size()) {
            const std::size_t comma = std::min(v.find(',', start), v.size());
            if (comma > start) names.push_back(v.substr(start, comma - start));
            start = comma + 1;
        }
    }
    return names;
}

// The ParaView collection beside a sequence of VTK meshes: the pattern's
// name up to its number (m_%04d.vtp -> m.pvd), in the same folder.
std::filesystem::path collectionName(const std::string& pattern) {
    const std::filesystem::path p(pattern);
    std::string stem = p.filename().string();
    stem = stem.substr(0, stem.find('%'));
    while (!stem.empty() && (stem.back() == '_' || stem.back() == '-' || stem.back() == '.')) stem.pop_back();
    return p.parent_path() / ((stem.empty() ? std::string("mesh") : stem) + ".pvd");
}

}  // namespace

int runMesh(const MeshJob& o, int threads) {
    const Result<MeshFormat> format = meshFormatOf(o.output);
    if (!format) return fail(format.error());
    const std::vector<std::string> interpolate = interpolatedNames(o.interpolate);
    if (!interpolate.empty() && *format == MeshFormat::Obj)
        return fail(makeUsageError(o.output, "--interpolate: OBJ has no place for vertex attributes; write .ply, "
                                             ".vtp or .vtk"));
    const bool vtk = *format == MeshFormat::Vtp || *format == MeshFormat::VtkLegacy;
    std::vector<std::filesystem::path> written;  // a VTK sequence's files, for its .pvd
    std::vector<double> numbers;
    auto frames = openFrames(o.input, nullptr, o.hPerSpacing);
    if (!frames) return fail(frames.error());
    if (auto st = frames->setSelection(o.select); !st) return fail(st.error());
    const std::size_t count = frames->count();
    if (auto st = frames->checkOutput(o.output, "mesh_%04d.ply"); !st) return fail(st.error());

    if (auto st = checkOptions(mesherOptionTable(), o.mesher); !st) return fail(st.error());
    MeshParams params = mesherParams(o.mesher, 0.0f, threads);
    if (count > 0) {
        auto first = frames->outputName(o.output, 0);
        if (!first) return fail(first.error());
        if (auto st = prepareOutputFolder(*first); !st) return fail(st.error());
    }
    installInterruptHandler("mesh");  // from here on Ctrl-C stops after the mesh in progress

    const bool tty = ::isatty(STDERR_FILENO) == 1;
    ProgressBar progress(count, "meshing");
    std::size_t kept = 0;
    for (std::size_t i = 0; i < count; ++i) {
        if (interrupted())
            return stopInterrupted(i ? "after mesh " + std::to_string(i) + " of " + std::to_string(count)
                                     : "before the first mesh",
                                   "the meshes written are whole: the same command with --resume writes the rest");
        auto formatted = frames->outputName(o.output, i);
        if (!formatted) return fail(formatted.error());
        const std::string out = *formatted;
        // --resume: a complete mesh stays; frame 0 is still read for the radius.
        const bool keep = o.resume && meshComplete(out);
        if (vtk) {
            written.push_back(out);
            numbers.push_back(double(frames->outputNumber(i)));
        }
        if (keep && i > 0) {
            ++kept;
            if (tty && count > 1) progress.update(i + 1);
            else std::cerr << "meniscus: kept " << out << " (complete)\n";
            continue;
        }
        std::string smoothingLength;
        auto set = frames->load(i, &smoothingLength);
        if (!set) return fail(set.error());
        printWarnings(*set);
        const std::string name = frames->files[i].string();
        if (auto st = checkCoordinates(set->positions, name); !st) return fail(st.error());
        if (i == 0) {
            // One radius for the whole sequence, so the surface does not breathe.
            std::string note;
            const auto radius = resolveRadius(o.radius, [&] { return defaultRadius(*set); }, &note);
            if (!note.empty()) {
                std::cerr << "meniscus: " << note << "\n";
                if (!smoothingLength.empty()) printSmoothingLengthNote(smoothingLength, frames->hPerSpacing);
            }
            if (!radius) return fail(Error{name, radius.error().message}.describe());
            params.radiusM = *radius;
        }
        if (keep) {
            ++kept;
            std::cerr << "meniscus: kept " << out << " (complete)\n";
            continue;
        }
        MeshStats stats;
        auto mesh = extractSurface(ParticleView::of(*set), params, &stats);
        if (!mesh) return fail(Error{name, mesh.error().message}.describe());
        // The sph field's own kernel support; the thesis field's is shorter
        // than the SPH neighbourhood, so its default h is used then.
        const float sphSupport = params.field == SurfaceField::Sph ? stats.supportM
                                                                   : defaults::kSphSupportRadii * params.radiusM;
        double smoothingMs = 0.0;
        if (o.smoothingIterations > 0) {
            const auto t0 = std::chrono::steady_clock::now();
            MeshSmoothing smoothing;
            smoothing.iterations = o.smoothingIterations;
            smoothing.weights = o.smoothingWeights != "off";
            if (auto st = smoothMesh(*set, smoothing, sphSupport, *mesh, threads); !st)
                return fail(Error{name, st.error().message}.describe());
            smoothingMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        }
        double attributesMs = 0.0;
        if (!interpolate.empty()) {
            const auto t0 = std::chrono::steady_clock::now();
            if (auto st = interpolateAttributes(*set, interpolate, sphSupport, *mesh, threads); !st)
                return fail(Error{name, st.error().message}.describe());
            attributesMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        }
        if (auto st = makeOutputFolders(out); !st) return fail(st.error());
        if (auto st = writeMesh(out, *mesh, *format); !st) return fail(st.error());
        if (o.stats)
            std::fprintf(stderr,
                         "meniscus: %s: %zu particles, %zu blocks (%zu with surface, %zu rounds), %zu cubes, %zu "
                         "corners, peak %.1f MB (estimated %.1f MB; one block %.2f MB), %d threads; blocks %.1f ms, extract %.1f ms, "
                         "weld and normals %.1f ms, total %.1f ms\n",
                         name.c_str(), stats.particles, stats.blocks, stats.blocksWithSurface, stats.rounds,
                         stats.cubesVisited, stats.cornersEvaluated, double(stats.peakBytes) / 1e6, double(stats.estimatedBytes) / 1e6,
                         double(stats.peakBlockBytes) / 1e6, stats.threads, stats.msBlocks, stats.msExtract,
                         stats.msMerge, stats.msTotal);
        // On a terminal a bar; otherwise (a log) one line per frame.
        if (tty && count > 1) progress.update(i + 1);
        else
            std::cerr << "meniscus: wrote " << out << " (" << mesh->vertexCount() << " vertices, "
                      << mesh->triangleCount() << " triangles, " << int(stats.msTotal + 0.5) << " ms"
                      << (o.smoothingIterations > 0
                              ? "; smoothing " + std::to_string(int(smoothingMs + 0.5)) + " ms" : std::string())
                      << (interpolate.empty() ? std::string()
                                              : "; attributes " + std::to_string(int(attributesMs + 0.5)) + " ms")
                      << ")\n";
    }
    // A sequence for ParaView: the collection listing every mesh (those kept
    // too) at its frame's number, opened as one time series.
    if (vtk && count > 1) {
        const std::filesystem::path pvd = collectionName(o.output);
        if (auto st = writePvd(pvd, written, numbers); !st) return fail(st.error());
        if (!tty || count == 1) std::cerr << "meniscus: wrote " << pvd.string() << " (" << count << " meshes)\n";
    }
    if (count > 1 && tty)
        std::cerr << "meniscus: wrote " << count - kept << " meshes to " << o.output
                  << (kept ? " (" + std::to_string(kept) + " already complete, kept)" : std::string()) << "\n";
    return 0;
}

}  // namespace meniscus::app
