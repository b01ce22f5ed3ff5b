#include "whitewater.h"

#include <cstdio>
#include <filesystem>
#include <utility>
#include <iostream>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "common.h"
#include "help_format.h"
#include "meniscus/io.h"
#include "meniscus/particles.h"
#include "meniscus/whitewater.h"
#include "progress.h"

namespace meniscus::app {

CLI::App* addWhitewaterCommand(CLI::App& app, WhitewaterOptions& o) {
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
    cmd->add_option("--radius", o.radius, "Fluid particle radius r in metres (default: estimated from the first frame)")
        ->group(group::kInput)
        ->check(CLI::PositiveNumber);
    addSelectOption(cmd, o.select);
    cmd->add_option("--fps", o.fps,
                    "Frames per second of the input (default: estimated from how far the particles of the first two "
                    "frames move along their velocities)")
        ->group(group::kInput)
        ->check(CLI::PositiveNumber);
    cmd->add_option("--limits", o.limits,
                    "Potential limits TA_MIN,TA_MAX,WC_MIN,WC_MAX,KE_MIN,KE_MAX: trapped air (m/s), wave crest "
                    "(curvature, no unit), kinetic energy (J/kg). Default: automatic, 0.1 and 1 times the mean of "
                    "each frame's largest value (one more pass over the input)")
        ->group(group::kGeneration)
        ->delimiter(',')
        ->expected(6);
    cmd->add_option("--scale", o.params.scale, "Diffuse particles made per second by a particle at full potential")
        ->group(group::kGeneration)
        ->capture_default_str();
    cmd->add_option("--trapped-air-rate", o.params.trappedAirRate,
                    "k_ta: weight of the trapped-air potential (a factor on --scale, no unit)")
        ->group(group::kGeneration)
        ->capture_default_str();
    cmd->add_option("--wave-crest-rate", o.params.waveCrestRate,
                    "k_wc: weight of the wave-crest potential (a factor on --scale, no unit)")
        ->group(group::kGeneration)
        ->capture_default_str();
    cmd->add_option("--lifetime", o.lifetime, "Foam lifetime MIN,MAX in seconds (default 2,5)")
        ->group(group::kMotion)
        ->delimiter(',')
        ->expected(2);
    cmd->add_option("--buoyancy", o.params.buoyancy, "Bubbles' buoyancy k_b, in multiples of -gravity")
        ->group(group::kMotion)
        ->capture_default_str();
    cmd->add_option("--drag", o.params.drag, "Bubbles' drag k_d toward the fluid's velocity, 0 to 1")
        ->group(group::kMotion)
        ->capture_default_str();
    cmd->add_option("--gravity", o.gravity, "Gravity X,Y,Z in m/s^2 (default 0,-9.81,0)")
        ->group(group::kMotion)
        ->delimiter(',')
        ->expected(3);
    cmd->add_option("--box", o.box,
                    "MINX,MINY,MINZ,MAXX,MAXY,MAXZ in metres (the container): diffuse particles leaving it dissolve. "
                    "Default: the fluid's region so far, grown by 4 r, open upward")
        ->group(group::kMotion)
        ->delimiter(',')
        ->expected(6);
    cmd->add_option("--spray-below", o.params.sprayBelow,
                    "Fewer fluid neighbours than this within 4 r (r: the particle radius): spray")
        ->group(group::kClasses)
        ->capture_default_str();
    cmd->add_option("--bubble-above", o.params.bubbleAbove, "More fluid neighbours than this: bubble (between: foam)")
        ->group(group::kClasses)
        ->capture_default_str();
    cmd->add_option("--max-particles", o.params.maxParticles, "Most diffuse particles alive at once")
        ->group(group::kGeneration)
        ->capture_default_str();
    cmd->add_option("--seed", o.params.seed, "Seed of the random numbers")
        ->group(group::kGeneration)
        ->capture_default_str();
    useGroupedHelp(cmd, {group::kInput, group::kGeneration, group::kClasses, group::kMotion, group::kOutput,
                         group::kPerformance});
    return cmd;
}

int runWhitewater(WhitewaterOptions o) {
    if (o.limits.size() == 6) {
        o.params.trappedAirMin = o.limits[0], o.params.trappedAirMax = o.limits[1];
        o.params.waveCrestMin = o.limits[2], o.params.waveCrestMax = o.limits[3];
        o.params.energyMin = o.limits[4], o.params.energyMax = o.limits[5];
        if (o.params.trappedAirMax == 0.0f || o.params.waveCrestMax == 0.0f || o.params.energyMax == 0.0f)
            return fail("--limits: every maximum must be above its minimum");
    }
    if (o.lifetime.size() == 2) o.params.lifetimeMinS = o.lifetime[0], o.params.lifetimeMaxS = o.lifetime[1];
    if (o.gravity.size() == 3) o.params.gravity = {o.gravity[0], o.gravity[1], o.gravity[2]};
    if (o.box.size() == 6) {
        o.params.box.extend({o.box[0], o.box[1], o.box[2]});
        o.params.box.extend({o.box[3], o.box[4], o.box[5]});
        if (!(o.box[0] < o.box[3] && o.box[1] < o.box[4] && o.box[2] < o.box[5]))
            return fail("--box: each minimum must be below its maximum");
    }
    if (std::string bad = sim::checkWhitewaterParams(o.params); !bad.empty()) return fail("whitewater: " + bad);

    auto frames = openFrames(o.input, nullptr);
    if (!frames) return fail(frames.error().describe());
    if (auto st = frames->setSelection(o.select); !st) return fail(st.error().describe());
    const std::size_t count = frames->count();
    if (auto st = frames->checkOutput(o.output, "diffuse_%04d.bgeo"); !st) return fail(st.error().describe());
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
    if (!first) return fail(first.error().describe());
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
        if (!second) return fail(second.error().describe());
        auto est = sim::estimateFrameInterval(ParticleView::of(*first), ParticleView::of(*second));
        if (!est) return fail(Error{frames->files[1].string(), est.error().message + " (give --fps)"}.describe());
        dt = *est;
        std::fprintf(stderr, "meniscus: %.3g frames per second, estimated from the first two frames (--fps sets it)\n",
                     1.0 / dt);
    }

    const bool tty = ::isatty(STDERR_FILENO) == 1;
    WhitewaterParams params = o.params;
    if (o.limits.empty()) {  // FoamGenerator's automatic mode: one pass to measure
        std::vector<sim::PotentialMaxima> maxima;
        ProgressBar progress(count, "measuring");
        for (std::size_t i = 0; i < count; ++i) {
            auto set = i == 0 ? Result<ParticleSet>(*first) : load(i);
            if (!set) return fail(set.error().describe());
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
    if (!gen) return fail(gen.error().describe());
    ProgressBar progress(count, "whitewater");
    for (std::size_t i = 0; i < count; ++i) {
        auto set = i == 0 ? std::move(first) : load(i);
        if (!set) return fail(set.error().describe());
        const std::string name = frames->files[i].string();
        auto stats = gen->step(ParticleView::of(*set), dt);
        if (!stats) return fail(Error{name, stats.error().message}.describe());
        auto out = frames->outputName(o.output, i);
        if (!out) return fail(out.error().describe());
        if (auto st = makeOutputFolders(*out); !st) return fail(st.error().describe());
        if (auto st = writeParticles(*out, sim::toParticleSet(gen->particles())); !st) return fail(st.error().describe());
        if (tty && count > 1) progress.update(i + 1);
        else
            std::fprintf(stderr,
                         "meniscus: wrote %s (%zu spray, %zu foam, %zu bubbles; %zu made, %zu dissolved; "
                         "potentials %.0f ms, advection %.0f ms, generation %.0f ms)\n",
                         out->c_str(), stats->spray, stats->foam, stats->bubbles, stats->generated, stats->removed,
                         stats->msPotentials, stats->msAdvect, stats->msGenerate);
    }
    if (count > 1 && tty) std::cerr << "meniscus: wrote " << count << " diffuse frames to " << o.output << "\n";
    return 0;
}

}  // namespace meniscus::app
