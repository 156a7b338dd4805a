#pragma once
// `xcut bench --suite solver`: the linear-solver stage (systems/solver/linear_solver.h) method by method on
// the same scenes, each ratio measured in one run against solver.linear = jacobi: steps per second,
// CG iterations per step, the largest residual, steps that needed a renewed factor or substeps, the
// factor's non-zeros and bytes per tet, peak memory; and the 2-thread step against the 1-thread step
// while another process keeps one core busy. The timed steps start after load, where the cholesky
// and amg methods build their kept preconditioner (systems/solver/linear_solver.h, prepare_linear_solver);
// that time is its own column. Each case runs three times (once with --tiny); its row is the median
// run, with the range. Two cases run their fastest method again without the projected first guess
// (solver.guess_history = 0), for the guess's share in the same run. A benchmark: it prints figures
// and writes CSV (results/bench_solver.csv; --tiny or --cases write results/bench_solver_quick.csv,
// never the record).
#include <string>
#include <vector>

namespace xcut {

struct SolverBenchOptions {
    bool tiny = false;          ///< small cases and few steps (CI, a quick look)
    std::string csv;            ///< default: results/bench_solver.csv, or ..._quick.csv when tiny
    bool progress = true;
    std::vector<std::string> cases;  ///< only these cases (all when empty)
    int repeats = 3;                 ///< timed runs of each case (the median is reported)
};

struct SolverBenchRow {
    std::string case_name, method;
    int tets = 0, steps = 0, threads = 2;
    double steps_per_s = 0, ms_per_step = 0, cg_per_step = 0, max_residual = 0;
    int refactored_steps = 0, substepped_steps = 0, factorizations = 0;
    double factor_bytes_per_tet = 0, rss_bytes_per_tet = 0;
    int guess_history = 0;      ///< solver.guess_history of the run (0: the previous step's solution)
    double load_setup_ms = 0;   ///< the kept preconditioner built at load, outside the timed steps
    int repeats = 1;            ///< timed runs of the case; the row is the median one
    double slowest_steps_per_s = 0, fastest_steps_per_s = 0;  ///< the range over the runs
    std::string failure;        ///< the NumericalError that stopped the run, if any
};

std::vector<SolverBenchRow> run_solver_bench(const SolverBenchOptions& options);
/// Prints the tables with the targets, writes the CSV; returns 0.
int solver_bench_command(const SolverBenchOptions& options);

}  // namespace xcut
