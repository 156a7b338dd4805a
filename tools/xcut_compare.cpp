// xcut compare SCENE: XFEM against snapping and subdivision on the same incisions (docs/compare.md).
#include "tools/studies/compare.h"
#include "tools/xcut_commands.h"

namespace xcut {

Command add_compare_command(CLI::App& app) {
    struct Options {
        CompareOptions compare;
        bool no_delay = false, no_plots = false;
    };
    auto o = std::make_shared<Options>();
    CompareOptions& c = o->compare;
    CLI::App* cmd = app.add_subcommand(
        "compare", "XFEM against snapping and subdivision on one scene: DOFs per cut, crossing delay, quality, step "
                   "time (CSV + PNG in out/<scene>/compare)");
    cmd->add_option("scene", c.scene, "Scene file with a bladed tool (its incision is repeated)")->required();
    cmd->add_option("--cuts", c.cuts, "Incisions, one after another, offset sideways")->check(CLI::Range(1, 200));
    cmd->add_option("--spacing", c.spacing, "Sideways distance between incisions [m] (default: automatic)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--threads,-j", c.threads, "OpenMP threads")->check(CLI::Range(1, 256));
    cmd->add_option("--output,-o", c.output, "Output directory (default out/<scene>/compare)");
    cmd->add_option("--set", c.overrides, "Override a scene field: field.path=value");
    cmd->add_flag("--no-delay-sweep", o->no_delay, "Skip the crossing-delay sweep (blade speeds x mesh sizes)");
    cmd->add_flag("--no-plots", o->no_plots, "CSVs only");
    cmd->add_flag("--quiet,-q", c.quiet, "No progress bars");
    return {cmd, [o] {
                o->compare.delay_sweep = !o->no_delay;
                o->compare.plots = !o->no_plots;
                return compare_command(o->compare);
            }};
}

}  // namespace xcut
