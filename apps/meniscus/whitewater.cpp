#include "whitewater.h"

#include <cstdio>
#include <filesystem>
#include <utility>
#include <iostream>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "common.h"
#include "help_format.h"
#include "interrupt.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/whitewater.h"
#include "progress.h"

namespace meniscus::app {

CLI::App* addWhitewaterCommand(CLI::App& app, WhitewaterJob& o) {
    auto* cmd = app.add_subcommand(
        "whitewater",
        "Generate spray, foam and air-bubble particles from a fluid sequence with velocities (Ihmsen et al. 2012, "
        "as SPlisHSPlasH's FoamGenerator), written as their own sequence (attributes velocity, id, type: 0 foam, 1 "
        "spray, 2 bubble, lifetime) for `render --diffuse`. The same particles for any --threads");
    cmd->add_option("input", o.input, "Fluid sequence: directory or pattern (frame_%04d.bgeo, data_*.bgeo), with velocities")
        ->group(group::kInput)
        ->required();
    cmd->add_option("-o,--output", o.output, "Output pattern, e.g. diffuse_%04d.bgeo (.bgeo, .bgeo.gz, .vtk, .vtu, .vtp, .ply)")
        ->group(group::kOutput)
        ->required();
    addRows(cmd, whitewaterOptionTable(), o);
    addSelectOption(cmd, o.select);
    useGroupedHelp(cmd, {group::kInput, group::kGeneration, group::kClasses, group::kMotion, group::kOutput,
                         group::kPerformance});
    return cmd;
}

int runWhitewater(const WhitewaterJob& o) {
    const auto made = whitewaterParams(o);
    if (!made) return fail(made.error());

    auto frames = openFrames(o.input, nullptr);
    if (!frames) return fail(frames.error());
    if (auto st = frames->setSelection(o.select); !st) return fail(st.error());
    const std::size_t count = frames->count();
    if (auto st = frames->checkOutput(o.output, "diffuse_%04d.bgeo"); !st) return fail(st.error());
    if (count > 0) {
        auto firstOut = frames->outputName(o.output, 0);
        if (!firstOut) return fail(firstOut.error());
        if (auto st = prepareOutputFolder(*firstOut); !st) return fail(st.error());
    }
    installInterruptHandler("frame");  // from here on Ctrl-C stops after the frame in progress
    const std::string resumeNote = "the frames written are whole: the same command with --resume writes the rest";
    auto load = [&](std::size_t i) -> Result<ParticleSet> {
        auto set = frames->load(i);
        if (!set) return set.error();
        const std::string name = frames->files[i].string();
        if (!set->find(kAttrVelocity) && set->size() > 0)
            return Error{name, "no velocity attribute: whitewater needs the fluid's velocities"};
        if (auto st = checkCoordinates(set->positions, name); !st) return st.error();
        return set;
    };

    auto first = load(0);
    if (!first) return fail(first.error());
    printWarnings(*first);
    std::string note;
    const auto resolved = resolveRadius(o.radius, [&] { return defaultRadius(*first); }, &note);
    if (!note.empty()) std::cerr << "meniscus: " << note << "\n";
    if (!resolved) return fail(Error{frames->files[0].string(), resolved.error().message}.describe());
    const float radius = *resolved;
    double dt = o.fps > 0.0 ? 1.0 / o.fps : 0.0;
    if (dt == 0.0) {
        if (count < 2) return fail("whitewater: one frame has no time between frames; give --fps");
        auto second = load(1);
        if (!second) return fail(second.error());
        auto est = sim::estimateFrameInterval(ParticleView::of(*first), ParticleView::of(*second));
        if (!est) return fail(Error{frames->files[1].string(), est.error().message + " (give --fps)"}.describe());
        dt = *est;
        std::fprintf(stderr, "meniscus: %.3g frames per second, estimated from the first two frames (--fps sets it)\n",
                     1.0 / dt);
    }

    const bool tty = ::isatty(STDERR_FILENO) == 1;
    WhitewaterParams params = *made;
    if (o.limits.empty()) {  // FoamGenerator's automatic mode: one pass to measure
        std::vector<sim::PotentialMaxima> maxima;
        ProgressBar progress(count, "measuring");
        for (std::size_t i = 0; i < count; ++i) {
            if (interrupted()) return stopInterrupted("while measuring the potentials", "nothing was written: run the command again");
            auto set = i == 0 ? Result<ParticleSet>(*first) : load(i);
            if (!set) return fail(set.error());
            auto pot = sim::computePotentials(ParticleView::of(*set), radius, params);
            if (!pot) return fail(Error{frames->files[i].string(), pot.error().message}.describe());
            maxima.push_back(sim::maximaOf(*pot));
            progress.update(i + 1);
        }
        params = sim::withAutomaticLimits(params, maxima);
        std::fprintf(stderr,
                     "meniscus: automatic limits: trapped air %.3g to %.3g m/s, wave crest %.3g to %.3g, kinetic "
                     "energy %.3g to %.3g J/kg (--limits sets them)\n",
                     params.trappedAirMin, params.trappedAirMax, params.waveCrestMin, params.waveCrestMax,
                     params.energyMin, params.energyMax);
    }

    auto gen = sim::WhitewaterGenerator::create(params, radius);
    if (!gen) return fail(gen.error());
    ProgressBar progress(count, "whitewater");
    std::size_t kept = 0;
    for (std::size_t i = 0; i < count; ++i) {
        if (interrupted())
            return stopInterrupted(i ? "after frame " + std::to_string(i) + " of " + std::to_string(count)
                                     : "before the first frame",
                                   resumeNote);
        auto set = i == 0 ? std::move(first) : load(i);
        if (!set) return fail(set.error());
        const std::string name = frames->files[i].string();
        auto stats = gen->step(ParticleView::of(*set), dt);
        if (!stats) return fail(Error{name, stats.error().message}.describe());
        auto out = frames->outputName(o.output, i);
        if (!out) return fail(out.error());
        // --resume: a complete frame stays; the generator stepped through it
        // above, as its particles carry over to the next frame.
        if (o.resume && particlesComplete(*out)) {
            ++kept;
            if (tty && count > 1) progress.update(i + 1);
            else std::cerr << "meniscus: kept " << *out << " (complete)\n";
            continue;
        }
        if (auto st = makeOutputFolders(*out); !st) return fail(st.error());
        if (auto st = writeParticles(*out, sim::toParticleSet(gen->particles())); !st) return fail(st.error());
        if (tty && count > 1) progress.update(i + 1);
        else
            std::fprintf(stderr,
                         "meniscus: wrote %s (%zu spray, %zu foam, %zu bubbles; %zu made, %zu dissolved; "
                         "potentials %.0f ms, advection %.0f ms, generation %.0f ms)\n",
                         out->c_str(), stats->spray, stats->foam, stats->bubbles, stats->generated, stats->removed,
                         stats->msPotentials, stats->msAdvect, stats->msGenerate);
    }
    if (count > 1 && tty)
        std::cerr << "meniscus: wrote " << count - kept << " diffuse frames to " << o.output
                  << (kept ? " (" + std::to_string(kept) + " already complete, kept)" : std::string()) << "\n";
    return 0;
}

}  // namespace meniscus::app
