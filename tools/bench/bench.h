#pragma once
// `xcut bench`: programs that print figures and write CSV, never timed tests.
//  --suite perf: steps per second of tissue_block at several tetrahedron counts, 1 and 2 threads,
//                CG iterations per step, time per scheduled system, bytes per tetrahedron; the
//                machine's roofline and the force kernel against it (tools/bench/bench_kernel.h); cut
//                update p50/p99 against mesh size (tools/bench/bench_cut.h); the same scene with and
//                without tools and visual mesh (tools/bench/bench_skip.h). Every table is a CSV in one
//                folder: <csv> and <csv stem>_{systems,roofline,kernel,cut,skip}.csv beside it.
//  --suite cut:  cut update time per quad and crossing delay (tools/bench/bench_cut.h).
#include <fmt/os.h>

#include <string>
#include <vector>

#include "tools/bench/roofline.h"
#include "engine/io/scene.h"

namespace xcut {

struct PerfBenchOptions {
    std::string scene = "scenes/tissue_block.json";
    std::vector<int> sizes{2000, 5000, 20000, 50000, 200000};  ///< target tetrahedron counts
    std::vector<int> threads{1, 2};
    int steps = 20;        ///< timed steps per run, after 2 warm-up steps
    std::string csv = "results/bench_perf.csv";
    int skip_tets = 20000;  ///< tetrahedra of the skip row's scene
    bool cut_rows = true;   ///< cut update p50/p99 at every size
    RooflineOptions roofline;
};

struct PerfBenchRow {
    int tets = 0, nodes = 0, threads = 0;
    double steps_per_s = 0, ms_per_step = 0, cg_per_step = 0, force_ms = 0, solver_ms = 0;
    double bytes_per_tet_components = 0;  ///< capacity of every component array / tets
    double bytes_per_tet_rss = 0;         ///< peak resident set of the process / tets (upper bound)
    double newton_iterations = 0;         ///< polar decomposition, mean per tetrahedron
    double product_ms = 0;                ///< one CG product K p (stiffness_product), mean of 10 [ms]
    double load_average = 0;              ///< the machine's 1-minute load average after the run (this run counts)
    std::vector<std::string> system_names;  ///< the schedule
    std::vector<double> system_ms;          ///< mean wall time per step of each scheduled system [ms]
};

std::vector<PerfBenchRow> run_perf_bench(const PerfBenchOptions& options, bool progress = true);
/// Runs every part of the perf suite, prints the tables (with the targets) and writes the CSVs; returns 0.
int perf_bench_command(const PerfBenchOptions& options);

/// The scene at `path` (with --set style `overrides`) with its grid resized to about `tets` tetrahedra.
Scene sized_scene(const std::string& path, int tets, const std::vector<std::string>& overrides = {});
/// "dir/stem.csv" -> "dir/stem_<part>.csv": the suite's other tables beside its main CSV.
std::string sibling_csv(const std::string& csv, const std::string& part);
/// Opens a CSV for writing, creating its folder.
fmt::ostream open_csv(const std::string& path);

/// A child process that keeps one core busy until stop_busy_process: the load a renderer or a
/// haptic thread puts beside the physics. -1 if it could not be started.
int start_busy_process();
void stop_busy_process(int pid);

/// The process's peak resident set so far [bytes] (VmHWM).
double peak_rss_bytes();
/// Returns freed memory to the system and starts the peak over from the resident set then (Linux:
/// /proc/self/clear_refs), so the next peak_rss_bytes() is one run's; false if the kernel refuses
/// (the peak then stays the process's).
bool reset_peak_rss();

/// Bytes held by the world's component arrays (capacities), for the memory budget.
struct World;
size_t world_bytes(const World& world);

}  // namespace xcut
