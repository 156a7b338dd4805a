// Problem 5 with the blade stopped inside a cell (xcut bench --suite accuracy): where the crack ends
// against where the blade stopped, in 3D. Each stop is scored against CalculiX's reference for a
// crack ending there (tools/reference/calculix_reference.py, graded toward that front).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <map>

#include "tools/bench/bench_accuracy.h"

namespace xcut {

void block_stop_sweep(const AccuracyBenchOptions& o, const std::string& cache, std::vector<ReferenceNote>& notes) {
    const CutBlockSpec grid;  // its front (10 mm down) on a grid plane at every level
    const int n = o.block_stop_level;
    const double h = grid.size.z() / cut_block_cells(grid, n).z();
    std::map<std::string, std::vector<double>> errors;
    for (int k = 0; k < o.block_stops; ++k) {
        CutBlockSpec stop = grid;
        stop.depth = grid.depth + (k + 0.5) / o.block_stops * h;
        stop.front_in_cell = true;
        const ExternalReference ref = calculix_reference(5, cut_block_parameters(stop), o.block_stop_reference_levels, cache);
        if (!ref.available) {
            notes.push_back({5, fmt::format("problem 5 blade stops: not run: {}", ref.why)});
            return;
        }
        const std::vector<Vec3> reference = reference_points(ref);
        for (const char* c : {"xfem", "xfem_tip", "snap"}) {
            const AccuracyRow r = cut_block_run(stop, n, c, reference);
            if (ref.error_estimate > 0.1 * r.error) {  // the suite's rule, as refuse_weak_reference
                notes.push_back({5, fmt::format("problem 5 blade stops: NOT scored: the reference at depth {:.6g} m has "
                                                "an error estimate {:.2g} %, more than 1/10 of {}'s error {:.2g} %",
                                                stop.depth, 100 * ref.error_estimate, c, 100 * r.error)});
                return;
            }
            errors[c].push_back(100 * r.error);
        }
    }
    for (const auto& [cutter, e] : errors) {
        const auto [lo, hi] = std::minmax_element(e.begin(), e.end());
        notes.push_back({5, fmt::format("problem 5 blade stops ({}, level {}, {} stops inside the cell below {:.6g} m "
                                        "deep): errors {:.2f} % -> spread {:.2f} points",
                                        cutter, n, o.block_stops, grid.depth, fmt::join(e, " "), *hi - *lo)});
    }
}

}  // namespace xcut
