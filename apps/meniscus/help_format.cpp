// `--help` laid out group by group (help_format.h).
#include "help_format.h"

#include <algorithm>
#include <memory>
#include <sstream>
#include <utility>

#include <CLI/CLI.hpp>

namespace meniscus::app {

namespace {

// Where `o` goes inside its group: named in `first` (by position there), the
// rest, named in `last` (by position there).
std::size_t rankIn(const HelpLayout& layout, const CLI::Option* o) {
    const auto named = [o](const std::vector<std::string>& names) {
        return std::find_if(names.begin(), names.end(), [o](const std::string& n) { return o->check_name(n); }) -
               names.begin();
    };
    const std::size_t first = named(layout.first), last = named(layout.last);
    if (first < layout.first.size()) return first;
    if (last < layout.last.size()) return layout.first.size() + 1 + last;
    return layout.first.size();
}

// CLI11's formatter with make_help printing the groups as `layout_` says.
class GroupedHelp : public CLI::Formatter {
public:
    explicit GroupedHelp(HelpLayout layout) : layout_(std::move(layout)) {}

    std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override {
        if (mode == CLI::AppFormatMode::Sub) return make_expanded(app);
        std::vector<const CLI::Option*> options =
            app->get_options([](const CLI::Option* o) { return !o->get_group().empty(); });
        // The parent's options that fall through to it from after the subcommand (--threads).
        const CLI::App* parent = app->get_parent();
        if (parent && app->get_fallthrough())
            for (const CLI::Option* o : parent->get_options()) {
                const auto& g = layout_.groups;
                if (std::find(g.begin(), g.end(), o->get_group()) != g.end() && o->nonpositional() &&
                    o != parent->get_help_ptr() && o != parent->get_help_all_ptr() && !o->check_lname("version"))
                    options.push_back(o);
            }
        std::stable_sort(options.begin(), options.end(), [this](const CLI::Option* a, const CLI::Option* b) {
            return rankIn(layout_, a) < rankIn(layout_, b);
        });
        std::vector<std::string> groups;
        for (const std::string& g : layout_.groups)
            if (g != group::kHelp) groups.push_back(g);
        for (const CLI::Option* o : options) {
            const std::string& g = o->get_group();
            if (g != group::kHelp && std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
        }
        groups.push_back(group::kHelp);

        std::ostringstream out;
        out << make_description(app) << make_usage(app, name);
        for (const std::string& g : groups) {
            std::string lines;
            for (const CLI::Option* o : options)
                if (o->get_group() == g) lines += make_option(o, o->get_positional());
            if (!lines.empty()) out << "\n" << g << ":\n" << lines;
        }
        out << make_subcommands(app, mode);
        out << '\n' << make_footer(app);
        return out.str();
    }

private:
    HelpLayout layout_;
};

}  // namespace

const HelpLayout& renderHelpLayout() {
    static const HelpLayout layout{
        .groups = {group::kInput, group::kCamera, group::kLook, group::kSurface, group::kExtras, group::kOutput,
                   group::kMovie, group::kPerformance, group::kCluster},
        .first = {"--output", "--view", "--threads", "--backend"},
        .last = {"--fluid", "--fluid-attribute"},
    };
    return layout;
}

void useGroupedHelp(CLI::App* cmd, HelpLayout layout) {
    if (CLI::Option* help = cmd->get_help_ptr()) help->group(group::kHelp);
    cmd->formatter(std::make_shared<GroupedHelp>(std::move(layout)));
}

void useGroupedHelp(CLI::App* cmd, std::vector<std::string> groups) {
    HelpLayout layout;
    layout.groups = std::move(groups);
    useGroupedHelp(cmd, std::move(layout));
}

void suffixGroups(CLI::App* cmd, std::size_t from, const std::string& suffix) {
    const std::vector<CLI::Option*> options = cmd->get_options();
    for (std::size_t i = from; i < options.size(); ++i)
        if (!options[i]->get_group().empty()) options[i]->group(options[i]->get_group() + suffix);
}

}  // namespace meniscus::app
