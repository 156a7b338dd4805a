#pragma once
// `xcut bench --suite cutstep`: real time through a cut. A scalpel cuts continuously through the
// skin (its default 2 mm cells, and refined to 1 and 0.7 mm: thin tissue, two or three elements
// through the thickness) and through tissue blocks of about 20k, 53k and 200k tetrahedra; every
// step of the full pipeline is timed (2 threads, no output). Per case: the median, p99 and max step
// over all steps, over the cut (the steps from the first that splits to the last: what a blade cutting
// meets, without the load's first sag) and over the steps that split elements, their ratios to the
// median step, CG
// iterations at those steps, how many steps built a preconditioner (a factor, a hierarchy) in the
// step and how many took one built off the step (and their longest wait), peak memory; the default skin and the 53k block again beside a process that keeps one core busy.
// Targets (issue #36): p99 <= 1.5x and max <= 2x the median step. A benchmark: it prints figures
// and writes results/bench_cutstep.csv (--tiny or --cases: results/bench_cutstep_quick.csv).
#include <string>
#include <vector>

namespace xcut {

struct CutStepBenchOptions {
    bool tiny = false;               ///< the default skin and a 5k block, few steps
    std::vector<std::string> cases;  ///< only these cases (all when empty)
    std::string csv = "results/bench_cutstep.csv";
    bool progress = true;
};

struct CutStepBenchRow {
    std::string case_name, load = "quiet", method;
    int tets = 0, steps = 0, split_steps = 0, dofs_end = 0;
    int builds = 0;   ///< steps that built a preconditioner in the step (a factor, a hierarchy)
    int swaps = 0;    ///< steps that took one built off the step
    double wait_max_ms = 0;  ///< the longest a step waited for one [ms]
    double median_ms = 0, p99_ms = 0, max_ms = 0;              ///< every step
    double split_median_ms = 0, split_max_ms = 0;              ///< the steps that split elements
    /// The cut: the steps from the first that split elements to the last (1-based, inclusive), their
    /// p99 and max [ms] (ratios to the run's median: a cut's steps against the run's).
    int cut_from = 0, cut_to = 0;
    double cut_p99_ms = 0, cut_max_ms = 0;
    double cg_median = 0, cg_split_median = 0, cg_split_max = 0;
    double peak_rss_mb = 0;  ///< the run's peak resident set (the process's when own_peak is false)
    bool own_peak = false;
    std::string failure;  ///< the NumericalError that stopped the run, if any
};

std::vector<CutStepBenchRow> run_cutstep_bench(const CutStepBenchOptions& options);
/// Prints the table with the targets and writes the CSV; returns 0.
int cutstep_bench_command(const CutStepBenchOptions& options);

}  // namespace xcut
