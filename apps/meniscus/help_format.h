// `--help` in groups, ordered by what people set first (docs/cli.md is the
// generated reference). Each option names its group (`->group(group::kCamera)`);
// useGroupedHelp installs a formatter that prints a command's groups in a given
// order, since CLI11 2.1.2 prints them in order of first appearance and its
// Formatter::make_groups is not virtual.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace meniscus::app {

// The group titles, shared by the commands whose options they group.
namespace group {
inline constexpr const char* kInput = "Input";            // what is read: input, --radius, --select
inline constexpr const char* kCamera = "Camera";          // size, eye, target, field of view
inline constexpr const char* kLook = "Look";              // material, light, background
inline constexpr const char* kSurface = "Surface";        // filter, iterations, anisotropy, ray cast, mesh
inline constexpr const char* kExtras = "Extras";          // noise, foam, whitening, spray, silhouettes, fluids
inline constexpr const char* kOutput = "Output";          // what is written, and how
inline constexpr const char* kMovie = "Movie";            // frame rate, quality, moving cameras
inline constexpr const char* kPerformance = "Performance";  // threads, backend, reduced resolution
inline constexpr const char* kCluster = "Cluster";        // shares of the frames: --shard, --split (MPI)
inline constexpr const char* kSimulation = "Simulation";  // simulate's (and view --simulate's) solver settings
inline constexpr const char* kGeneration = "Generation";  // whitewater: how many diffuse particles are made
inline constexpr const char* kClasses = "Classes";        // whitewater: spray, foam or bubble
inline constexpr const char* kMotion = "Motion";          // whitewater: how they move and dissolve
inline constexpr const char* kHelp = "Help";              // -h,--help, printed last
}  // namespace group

// How a command's help is laid out: its groups in order (then any other in
// order of first appearance, then -h,--help), and inside a group, the options
// named in `first` ahead of the rest and those in `last` after it, each in
// the list's order; the others stay in the order they were added.
struct HelpLayout {
    std::vector<std::string> groups;
    std::vector<std::string> first;  // option names, e.g. "--output", "--threads"
    std::vector<std::string> last;
};

// `render`'s layout, which demo, view and compare share: Input, Camera,
// Look, Surface, Extras, Output, Movie, Performance, Cluster (--output and
// --view lead Output, --threads and --backend lead Performance, the several
// fluids end Extras).
const HelpLayout& renderHelpLayout();

// Makes `cmd`'s help print its options group by group as `layout` says.
// Positionals are listed in their own group (the input under Input), and the
// parent's options that also work after the subcommand (--threads) in theirs
// when `layout.groups` names it. Options in group "" stay hidden.
void useGroupedHelp(CLI::App* cmd, HelpLayout layout);
// The same with the groups alone (inside each, the options in the order added).
void useGroupedHelp(CLI::App* cmd, std::vector<std::string> groups);

// Appends `suffix` to the group of every option of `cmd` from the `from`-th
// on (those in no group left hidden): simulate's image options become
// "Camera (with --render)", ...
void suffixGroups(CLI::App* cmd, std::size_t from, const std::string& suffix);

}  // namespace meniscus::app
