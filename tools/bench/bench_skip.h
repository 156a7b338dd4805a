#pragma once
// "Skip what the scene doesn't need" (part of `xcut bench --suite perf`): the benchmark scene run
// with a scalpel (blade and handle), a visual surface and a collision surface, and without them.
// The scheduler drops a system whose inputs the world lacks (engine/scheduler.h), so a skipped
// system is never called: its time is exactly zero, and the bare scene's step costs only what runs.
#include <string>
#include <vector>

#include "tools/bench/bench.h"

namespace xcut {

struct SkipBenchRow {
    std::string scene;        ///< "with" (tools, visual and collision surfaces) or "without"
    std::string system;       ///< every registered system, pipeline order
    bool scheduled = false;
    int calls = 0;            ///< timed steps in which the system ran
    double ms_per_step = 0;   ///< mean over the timed steps [ms]; 0 when never called
    double step_ms = 0;       ///< the whole step, mean [ms]
};

/// Both scenes at about `tets` tetrahedra, `steps` timed steps after 2 warm-up steps each.
std::vector<SkipBenchRow> run_skip_bench(const std::string& scene, int tets, int steps);
/// Runs it at options.skip_tets, prints the table and writes <csv stem>_skip.csv.
void skip_row(const PerfBenchOptions& options);

}  // namespace xcut
