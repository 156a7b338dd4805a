#pragma once
// `xcut bench`: programs that print figures and write CSV, never timed tests.
//  --suite perf: steps per second of tissue_block at several tetrahedron counts, 1 and 2 threads,
//                CG iterations per step, per-system time, bytes per tetrahedron.
//  --suite cut:  cut update time per quad and crossing delay (engine/bench_cut.h).
#include <string>
#include <vector>

namespace xcut {

struct PerfBenchOptions {
    std::string scene = "scenes/tissue_block.json";
    std::vector<int> sizes{5000, 20000, 50000, 200000};  ///< target tetrahedron counts
    std::vector<int> threads{1, 2};
    int steps = 20;        ///< timed steps per run, after 2 warm-up steps
    std::string csv = "results/bench_perf.csv";
};

struct PerfBenchRow {
    int tets = 0, nodes = 0, threads = 0;
    double steps_per_s = 0, ms_per_step = 0, cg_per_step = 0, force_ms = 0, solver_ms = 0;
    double bytes_per_tet_components = 0;  ///< capacity of every component array / tets
    double bytes_per_tet_rss = 0;         ///< peak resident set of the process / tets (upper bound)
};

std::vector<PerfBenchRow> run_perf_bench(const PerfBenchOptions& options, bool progress = true);
/// Prints the table (with the targets) and writes the CSV; returns 0.
int perf_bench_command(const PerfBenchOptions& options);

/// Bytes held by the world's component arrays (capacities), for the memory budget.
struct World;
size_t world_bytes(const World& world);

}  // namespace xcut
