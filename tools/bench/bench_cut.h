#pragma once
// Cut benchmark (`xcut bench --suite cut`): a scalpel drawn through tissue blocks of growing size;
// per quad, the cutter's update time (quad search, crossings, lists) and the enrichment's (split,
// DOFs, virtual elements, masses), and the crossing delay of every split element (paper Fig. 12).
#include <string>
#include <vector>

namespace xcut {

struct CutBenchOptions {
    std::vector<int> sizes{5000, 20000, 50000, 200000};  ///< target tetrahedron counts
    double speed = 0.05;      ///< blade speed [m/s]
    double dt = 0.01;         ///< step [s]
    std::string csv = "results/bench_cut.csv";
    bool bvh_every_quad = false;  ///< candidate search: Embree BVH for every quad instead of the neighbourhood
    /// Several cuts per element: cutter.recut on, and two more scalpels cross the first's wound.
    bool recut = false;
};

struct CutBenchRow {
    std::string search;   ///< "neighbourhood", "bvh", or "recut" (neighbourhood, three scalpels, cutter.recut on)
    int tets = 0;
    int quads = 0;
    int splits = 0;
    int cut_again = 0;    ///< mesh elements whose cut holds more than one line at the end
    double quad_p50_ms = 0, quad_p99_ms = 0;      ///< CutSystem per quad
    double update_p50_ms = 0, update_p99_ms = 0;  ///< CutSystem + EnrichmentSystem per step with a quad
    /// The step with the largest update: the whole, and its CutSystem's and EnrichmentSystem's parts [ms].
    double update_max_ms = 0, worst_cutter_ms = 0, worst_enrichment_ms = 0;
    double delay_p50_s = 0, delay_p99_s = 0;      ///< crossing delay, simulated time
};

/// The benchmark body: a 100 x 100 x 50 mm block of about `tets` tetrahedra, base free, with a
/// scalpel (edge 20 mm deep) drawn across it along x at `speed` [m/s]. Shared by the cut and
/// mapping suites.
struct World;
World block_with_scalpel(int tets, double speed);

/// The p-quantile (0..1) of v, nearest rank; 0 for an empty list.
double percentile(std::vector<double> v, double p);

std::vector<CutBenchRow> run_cut_bench(const CutBenchOptions& options);
/// Prints the rows as a table and writes them to the CSV at `path`.
void write_cut_rows(const std::vector<CutBenchRow>& rows, const std::string& path);
/// Prints the table and writes the CSV; returns 0.
int cut_bench_command(const CutBenchOptions& options);

}  // namespace xcut
