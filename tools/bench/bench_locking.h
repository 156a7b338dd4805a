#pragma once
// `xcut bench --suite locking`: problem 3 (the clamped beam under its own weight, 20n x n x n cells)
// at Poisson's ratios 0, 0.3, 0.45 and 0.49, with the linear tetrahedron and the quadratic one
// (components/quadratic_elements.h), each against CalculiX's C3D20 reference for that ratio
// (tools/reference/calculix_reference.py, extrapolated); and Cook's membrane in plane strain at
// nu 0.3 and 0.49 against CalculiX's CPE8R (docs/verification.md problem 14); and problem 5 (a block cut
// part-way, pulled apart) at nu 0.3, 0.45 and 0.49 with both cutters on linear tetrahedra. Per run: DOFs,
// CPU time, CG iterations, the error (tip deflection; the block: L2 at sample points). The verdicts: per
// ratio and element, the fewest DOFs with an error within 2 % (target: <= 10k DOFs at every ratio), the
// error at equal CPU time; for the block, each level's error at nu 0.45 and 0.49 against 0.3. A benchmark:
// prints figures and writes results/bench_locking.csv (--tiny: results/bench_locking_quick.csv).
#include <string>
#include <vector>

namespace xcut {

struct LockingBenchOptions {
    bool tiny = false;  ///< two ratios, two levels each, the reference on two levels
    std::string csv = "results/bench_locking.csv";
    std::string cache_dir;  ///< empty: the user's cache (default_cache_dir)
};

struct LockingBenchRow {
    std::string problem = "beam";  ///< "beam" (problem 3), "cook" (Cook's membrane, problem 14) or "block" (problem 5)
    std::string element;   ///< "linear" or "quadratic"; for "block" the cutter: "xfem" or "snap" on linear tetrahedra, "xfem-quadratic"
    double poisson = 0;    ///< nu [-]
    int n = 0;             ///< cells across the beam (block: along its length)
    int dofs = 0;
    double cpu_s = 0, wall_s = 0;
    int newton = 0, cg = 0;
    double value = 0, reference = 0;  ///< tip deflection, corner's displacement; block: RMS sample displacement [m]
    double error = 0;      ///< value / reference - 1; block: relative L2 error at the samples (>= 0) [-]
    std::string reference_source;
};

/// Problem 5's rows (tools/bench/bench_locking_cut.cpp): the cut block at nu 0.3, 0.45 and 0.49 (tiny:
/// 0.3, 0.49), each cutter (element "xfem" or "snap", linear tetrahedra) against CalculiX's C3D20 for that
/// ratio, appended to rows.
void cut_block_rows(const LockingBenchOptions& options, const std::string& cache, std::vector<LockingBenchRow>& rows,
                    std::vector<std::string>* notes);
/// One line per cutter and level: its error at nu 0.3, and at each higher ratio run with its ratio to that, CG and CPU.
std::vector<std::string> cut_block_lines(const std::vector<LockingBenchRow>& rows);
/// Cook's membrane's rows (tools/bench/bench_cook.cpp), appended to rows.
void cook_rows(const LockingBenchOptions& options, const std::string& cache, std::vector<LockingBenchRow>& rows,
               std::vector<std::string>* notes);
std::vector<LockingBenchRow> run_locking_bench(const LockingBenchOptions& options, std::vector<std::string>* notes = nullptr);
/// One line per ratio and element: the fewest DOFs within 2 %, and the error at the other element's CPU time.
std::vector<std::string> locking_summary(const std::vector<LockingBenchRow>& rows);
int locking_bench_command(const LockingBenchOptions& options);

}  // namespace xcut
