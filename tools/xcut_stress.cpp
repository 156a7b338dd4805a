// xcut stress: the stability suite (docs/verification.md problems 7-9); exit 1 if an invariant broke.
#include <filesystem>

#include "tools/studies/stress.h"
#include "tools/xcut_commands.h"

namespace xcut {

Command add_stress_command(CLI::App& app) {
    auto o = std::make_shared<StressOptions>();
    CLI::App* cmd = app.add_subcommand(
        "stress", "Stability stress suite (docs/verification.md problems 7-9); exit 1 if an invariant broke");
    cmd->add_option("--count", o->count, "Random blade trajectories (problem 8)")->check(CLI::NonNegativeNumber);
    cmd->add_option("--budget", o->budget_s, "Wall-time budget for problem 8 [s]")->check(CLI::PositiveNumber);
    cmd->add_option("--seed", o->seed, "Random seed (reproducible)");
    cmd->add_option("--csv", o->csv, "CSV of every case");
    cmd->add_option("--front", o->front, "Problem 8's cutter.front: semi (the paper's) or progressive")
        ->check(CLI::IsMember({"semi", "progressive"}));
    cmd->add_option("--blades", o->blades, "Problem 8's scalpels per trajectory: 1, or 2 to this many at once "
                                           "(crossing in one step, stabs, blades with a face)")
        ->check(CLI::Range(1, 4));
    cmd->add_flag("--tip", o->tip, "Problem 8 in 2D with crack tips at the blades (a skin patch, random trajectories "
                                   "and tip radii; --front and --blades do not apply)");
    cmd->add_flag("--fronts", o->fronts, "Problem 8 in 3D with crack fronts at the blades (the slab's random "
                                         "trajectories, some blades deeper than the slab, and random zone radii; "
                                         "--front, --blades, --element and --recut do not apply)");
    cmd->add_flag("--loops", o->loops, "Problem 8 as closed loops in 2D: a scalpel round a random ellipse in a skin "
                                       "patch, a cross-cut through its lens in two of three; the pieces freed are "
                                       "checked against the regions the paths enclose (--front and --blades do not apply)");
    cmd->add_option("--element", o->element, "Problem 8's tissue: linear or quadratic tetrahedra (docs/elements.md)")
        ->check(CLI::IsMember({"linear", "quadratic"}));
    cmd->add_option("--newton", o->newton, "Problem 8's steps iterated by Newton to 1e-9, at most this many times "
                                           "(1, the default: the paper's once-linearized step)")
        ->check(CLI::Range(1, 1000));
    cmd->add_flag("--recut", o->recut, "Problem 8 with \"cutter.recut\": true (elements already cut are cut again; 3D "
                                       "with --blades: scalpels crossing each other's wounds)");
    cmd->add_option("--only", o->only, "Run only problem 8's trajectory of this index (as a full run of the same "
                                       "--seed, --front and --blades numbers them), to reproduce one case")
        ->check(CLI::NonNegativeNumber);
    return {cmd, [o, cmd] {
                o->csv_given = cmd->count("--csv") > 0;
                if (!o->csv_given && o->front != "semi") o->csv = "results/bench_stress_" + o->front + ".csv";
                if (o->tip && (o->front != "semi" || o->blades > 1))
                    throw CLI::ValidationError("--tip", "crack tips follow the semi-progressive front's single blade: "
                                                        "without --front and --blades");
                if (o->tip && o->element != "linear")
                    throw CLI::ValidationError("--tip", "crack tips are 2D: the linear triangle, without --element");
                if (!o->csv_given && o->tip) o->csv = "results/bench_stress_tip.csv";
                if (o->fronts && (o->tip || o->loops || o->front != "semi" || o->blades > 1 || o->element != "linear" ||
                                  o->recut))
                    throw CLI::ValidationError("--fronts", "crack fronts follow the semi-progressive front's single blade "
                                                           "on linear tetrahedra: without --tip, --loops, --front, "
                                                           "--blades, --element and --recut");
                if (!o->csv_given && o->fronts) o->csv = "results/bench_stress_fronts.csv";
                if (o->loops && (o->tip || o->front != "semi" || o->blades > 1 || o->element != "linear" || o->recut))
                    throw CLI::ValidationError("--loops", "closed loops are drawn in 2D by the semi front's scalpels: "
                                                          "without --tip, --front, --blades, --element and --recut");
                if (!o->csv_given && o->loops) o->csv = "results/bench_stress_loops.csv";
                if (!o->csv_given && o->element != "linear")
                    o->csv = std::filesystem::path(o->csv).replace_extension().string() + "_" + o->element + ".csv";
                if (!o->csv_given && o->newton > 1)
                    o->csv = std::filesystem::path(o->csv).replace_extension().string() + "_newton.csv";
                if (o->recut && (o->tip || o->element != "linear"))
                    throw CLI::ValidationError("--recut", "elements are cut again on linear tetrahedra without crack tips");
                if (!o->csv_given && o->blades > 1)
                    o->csv = std::filesystem::path(o->csv).replace_extension().string() + "_blades.csv";
                if (!o->csv_given && o->recut)
                    o->csv = std::filesystem::path(o->csv).replace_extension().string() + "_recut.csv";
                return stress_command(*o);
            }};
}

}  // namespace xcut
