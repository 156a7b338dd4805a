#pragma once
// `xcut bench --suite accuracy`: run time against error (docs/verification.md problems 3, 5 and 6) at
// several resolutions, the XFEM cutter beside the snapping-and-subdivision baseline:
//  3. cantilever under its own weight (no cut, one series "uncut": both cutters would solve the same
//     uncut mesh), error = |delta - delta_ref| / delta_ref;
//  5. block with a partial planar cut, pulled apart, error = relative L2 norm of the displacement at
//     fixed sample points against the reference;
//  6. single edge notched tension plate, error = |CMOD - CMOD_ref| / CMOD_ref.
// The references: CalculiX's quadratic elements, extrapolated, when it is installed
// (tools/studies/calculix_reference.h); else beam theory (3), the conforming linear-tet reference
// (5, tools/studies/crack_reference.h) and Tada, Paris & Irwin's handbook (6), and the summary says so.
// Each run: build the mesh, cut it (scripted planar cut), solve the static equilibrium; its run time
// is the wall time of cut + solve, its CPU time the process's over the same span (all threads): the
// cutters are compared at equal CPU time, which another process on the machine does not inflate.
// Writes one CSV row per run and, with python3-matplotlib, one PNG per problem (error against CPU
// time, log-log; tools/report/plot_accuracy.py). The CSV is complete without it.
#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tools/studies/accuracy_problems.h"
#include "tools/studies/calculix_reference.h"

namespace xcut {

struct AccuracyBenchOptions {
    std::vector<int> problems{3, 5, 6};
    std::vector<int> cantilever_levels{1, 2, 3, 4, 5, 8, 11, 14};  ///< n: 20n x n x n cells (14: 329k tets)
    std::vector<int> block_levels{8, 12, 16, 24, 32};    ///< cells along the block's length (multiples of 4)
    /// Problem 5 with snapping alone at these further levels: the front-enriched XFEM's finest level
    /// takes more CPU time than snapping's, so without them it is not compared.
    std::vector<int> block_snap_levels{40};
    int block_reference = 80;                            ///< cells along L of the conforming reference
    std::vector<int> plate_levels{10, 20, 40, 80, 160, 320};  ///< cells across the plate's width (even)
    /// Problem 6 with snapping alone at these further levels (cells across the width, even): the
    /// tip-enriched XFEM's finest level takes 2.5-3x the CPU time of snapping's, so without them it
    /// lies outside snapping's CPU-time range and is not compared (480: 1.4 M DOFs, 2.3 GB).
    std::vector<int> plate_snap_levels{480};
    /// Problem 6 on 6-node triangles (XFEM, `xfem-quadratic`): cells across the width (even).
    std::vector<int> plate_quadratic_levels{4, 8, 16, 32, 64, 128};
    /// The independent references' levels (tools/studies/calculix_reference.h), coarse to fine:
    /// cells across the beam's height (3), along the block's length (5), across the plate (6).
    std::vector<int> cantilever_reference_levels{1, 2, 3, 4};
    std::vector<int> block_reference_levels{8, 16, 32, 64};
    std::vector<int> plate_reference_levels{10, 20, 40, 80};
    /// Problem 6 also at these a / W, at the finest plate level, against their own references
    /// (a / W times the finest level must be an integer: the tip on a grid line).
    std::vector<double> crack_ratios{0.2, 0.3, 0.4, 0.6};
    std::vector<int> sweep_reference_levels{20, 40, 80, 160};  ///< their references' levels
    /// Problem 6 with the blade stopped at `stops` positions inside one cell past the tip, at level
    /// `stop_level`: each cutter's error against a reference for the crack the blade made (0: none).
    int stop_level = 80, stops = 10;
    std::vector<int> stop_reference_levels{10, 20, 40, 80};  ///< their references' levels
    /// Problem 5 with the blade stopped at `block_stops` depths inside the cell below the grid plane
    /// 10 mm down, at level `block_stop_level` (0 stops: none), each against its own reference.
    int block_stop_level = 16, block_stops = 5;
    std::vector<int> block_stop_reference_levels{8, 16, 32};
    std::string csv = "results/bench_accuracy.csv";      ///< PNGs beside it: accuracy_problem<k>.png
    std::string cache_dir;                               ///< default: $XDG_CACHE_HOME/xcut/accuracy (~/.cache/xcut/accuracy)
    /// One thread by default: the suite compares methods, not parallel scaling, and single-thread
    /// timings stay meaningful on a shared machine (an oversubscribed OpenMP team can be 20x slower).
    int threads = 1;
    bool plots = true;
    bool progress = true;

    /// The CI configuration: every problem at 3-4 small resolutions, a coarse reference (seconds).
    static AccuracyBenchOptions tiny();
};

struct AccuracyRow {
    int problem = 0;
    std::string cutter;           ///< xfem, snap; "uncut" for problem 3
    int resolution = 0;           ///< the level: cells across (3), along L (5), across W (6)
    double element_size = 0.0;    ///< cell edge along the resolution's axis [m]
    int dofs = 0;                 ///< dim x DOF nodes after the cut
    int split = 0;                ///< mesh elements the cut split
    double run_s = 0.0;           ///< wall time of cut + static solve [s]
    double cpu_s = 0.0;           ///< CPU time of the process over the same span, every thread's [s]
    int newton = 0, cg = 0;       ///< Newton iterations, CG iterations summed
    double value = 0.0;           ///< tip deflection (3), RMS sample displacement (5), CMOD (6) [m]
    double reference = 0.0;       ///< its reference [m]
    double error = 0.0;           ///< relative error [-]
};

/// What a problem was scored against: one line for the summary.
struct ReferenceNote {
    int problem = 0;
    std::string line;
};
/// Runs every problem at every level; throws std::invalid_argument on a bad option. With CalculiX
/// installed, problems 3, 5 and 6 are scored against its quadratic-element reference; a problem
/// whose reference's own error estimate is above 1/10 of the smallest error it would score is not
/// scored (its rows are left out, and `notes` says so).
std::vector<AccuracyRow> run_accuracy_bench(const AccuracyBenchOptions& options, std::vector<ReferenceNote>* notes = nullptr);
/// Columns: problem,cutter,resolution,element_size_m,dofs,split,run_time_s,cpu_time_s,newton,cg_iterations,
/// value_m,reference_m,error; then the summary lines, each as a comment ("# ...").
void write_accuracy_csv(const std::string& path, const std::vector<AccuracyRow>& rows,
                        const std::vector<std::string>& summary = {});
/// One run of a cutter set against the other cutter's error-against-CPU-time front.
struct FrontComparison {
    const AccuracyRow* run = nullptr;
    double other_error = 0.0;  ///< the other cutter's error at this CPU time, interpolated log-log; 0: outside its range
    double ratio = 0.0;        ///< run's error / other_error (below 1: this run is the more accurate); 0: outside
};
/// Every `cutter` (an XFEM variant) and `other` (snapping by default) run of `problem`, each against
/// the other's front (its runs sorted by CPU time, interpolated log-log between the two that bracket
/// this run's).
std::vector<FrontComparison> compare_fronts(const std::vector<AccuracyRow>& rows, int problem,
                                            const std::string& cutter = "xfem", const std::string& other = "snap");
/// The verdicts, one line each: problem 3's finest and Richardson-extrapolated deflection; for
/// problems 5 and 6, every run against the other cutter at equal CPU time, and the levels where
/// each cutter wins; problem 6's finest CMOD against the 5 % tolerance. No averaged verdict.
std::vector<std::string> accuracy_summary(const std::vector<AccuracyRow>& rows, const std::vector<ReferenceNote>& notes = {});
/// Prints the table and the targets, writes the CSV (and plots); returns 0.
int accuracy_bench_command(const AccuracyBenchOptions& options);

/// A run under kShortRun s of CPU time is repeated, kRepeats runs in all (each from a fresh world: the
/// errors are the same), and keeps the median CPU and wall times: one run of 5-40 ms on this shared
/// machine varies by 30 % and more (cold pages, the host's load), which moves a comparison at equal
/// CPU time as much as the methods do.
constexpr double kShortRun = 0.1;
constexpr int kRepeats = 5;
template <class Run>
AccuracyRow median_if_short(Run&& run) {
    AccuracyRow row = run();
    if (row.cpu_s >= kShortRun) return row;
    std::vector<double> cpu{row.cpu_s}, wall{row.run_s};
    for (int k = 1; k < kRepeats; ++k) {
        const AccuracyRow again = run();
        cpu.push_back(again.cpu_s), wall.push_back(again.run_s);
    }
    std::sort(cpu.begin(), cpu.end());
    std::sort(wall.begin(), wall.end());
    row.cpu_s = cpu[kRepeats / 2], row.run_s = wall[kRepeats / 2];
    return row;
}

/// Problem 5 on `spec` with n cells along L, cut by `cutter` (xfem or snap) and solved: its error is
/// the relative L2 norm of the displacement at cut_block_samples(spec) against `reference` there.
AccuracyRow cut_block_run(const CutBlockSpec& spec, int n, const char* cutter, const std::vector<Vec3>& reference);
/// Problem 5 with the blade stopped at o.block_stops depths inside the cell below the front's grid
/// plane (d = 10 mm + (k + 1/2) h / stops, level o.block_stop_level), each cutter (xfem: the semi
/// front's crack, which ends where the last fully crossed elements end; xfem_tip: a front where the
/// blade stopped, as a blade carries it; snap) against CalculiX's reference for that depth: one
/// line per cutter in `notes` with its errors and their spread (tools/bench/bench_accuracy_stops.cpp).
void block_stop_sweep(const AccuracyBenchOptions& o, const std::string& cache, std::vector<ReferenceNote>& notes);
/// Problem 5's parameters as tools/reference/calculix_reference.py reads them (the sample points included).
nlohmann::json cut_block_parameters(const CutBlockSpec& spec);
/// Problem 5's reference displacements, one point per three values [m].
std::vector<Vec3> reference_points(const ExternalReference& ref);

/// CPU time of the whole process, every thread's [s] (CLOCK_PROCESS_CPUTIME_ID).
double process_cpu_seconds();
/// The user's cache directory for references (XDG Base Directory: $XDG_CACHE_HOME, else ~/.cache),
/// never beside the binary: an installed xcut may sit in a directory its user cannot write.
std::string default_cache_dir();

}  // namespace xcut
