// Problem 5 (the block with a partial planar cut, pulled apart: docs/verification.md) at nu 0.3, 0.45
// and 0.49 for `xcut bench --suite locking`: what near incompressibility costs a cut scene, with either
// cutter on linear tetrahedra and on quadratic ones (docs/elements.md), against CalculiX's C3D20
// reference for each ratio (tools/reference/calculix_reference.py, extrapolated). Error: relative L2
// norm of the displacement at the suite's sample points (tools/bench/bench_accuracy.h).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "tools/bench/bench_accuracy.h"
#include "tools/bench/bench_locking.h"

namespace xcut {

void cut_block_rows(const LockingBenchOptions& o, const std::string& cache, std::vector<LockingBenchRow>& rows,
                    std::vector<std::string>* notes) {
    const std::vector<int> levels = o.tiny ? std::vector<int>{4, 8} : std::vector<int>{8, 12, 16, 24, 32};
    // tiny: a reference three levels finer than its runs, so its own error stays under 1/10 of theirs
    const std::vector<int> reference_levels = o.tiny ? std::vector<int>{8, 16, 32} : std::vector<int>{8, 16, 32, 64};
    const std::vector<double> ratios = o.tiny ? std::vector<double>{0.3, 0.49} : std::vector<double>{0.3, 0.45, 0.49};
    for (double nu : ratios) {
        CutBlockSpec spec;
        spec.poisson = nu;
        spec.reference_grading = 1.0;  // a uniform grid (tools/reference/calculix_reference.py: graded cells lock at 0.49)
        const ExternalReference ref = calculix_reference(5, cut_block_parameters(spec), reference_levels, cache);
        if (!ref.available) {
            if (notes) notes->push_back(fmt::format("block nu {}: no reference ({}): not run", nu, ref.why));
            continue;
        }
        const std::string source = fmt::format("CalculiX C3D20 levels {}, extrapolated (own error {:.2g} %)",
                                               fmt::join(ref.levels, " "), 100 * ref.error_estimate);
        if (notes)
            notes->push_back(fmt::format("block nu {}: reference at {} sample points, {}", nu, ref.values.size() / 3, source));
        const std::vector<Vec3> reference = reference_points(ref);
        // XFEM on quadratic tetrahedra (docs/elements.md) at levels of as many DOFs as the linear ones'
        const std::vector<int> quadratic_levels = o.tiny ? std::vector<int>{4} : std::vector<int>{4, 8, 12, 16};
        std::vector<std::pair<const char*, int>> runs;
        for (int n : levels)
            for (const char* cutter : {"xfem", "snap"}) runs.emplace_back(cutter, n);
        for (int n : quadratic_levels) runs.emplace_back("xfem-quadratic", n);
        for (int n : quadratic_levels) runs.emplace_back("xfem-quadratic-p0", n);
        for (int n : quadratic_levels) runs.emplace_back("snap-quadratic", n);
        for (const auto& [cutter, n] : runs) {
            const AccuracyRow a = median_if_short([&] { return cut_block_run(spec, n, cutter, reference); });
            LockingBenchRow row;
            row.problem = "block";
            row.element = cutter;
            row.poisson = nu, row.n = n, row.dofs = a.dofs;
            row.cpu_s = a.cpu_s, row.wall_s = a.run_s;
            row.newton = a.newton, row.cg = a.cg;
            row.value = a.value, row.reference = a.reference, row.error = a.error;
            row.reference_source = source;
            if (ref.error_estimate > 0.1 * a.error) {  // the accuracy suite's rule: a reference 10 x finer
                if (notes)
                    notes->push_back(fmt::format("block nu {} {} n {}: NOT scored: the reference's own error {:.2g} % is "
                                                 "more than 1/10 of the run's {:.2g} %", nu, cutter, n,
                                                 100 * ref.error_estimate, 100 * a.error));
                continue;
            }
            rows.push_back(row);
        }
    }
}

std::vector<std::string> cut_block_lines(const std::vector<LockingBenchRow>& rows) {
    std::map<std::pair<std::string, int>, std::map<double, const LockingBenchRow*>> by;  // (cutter, n) -> nu -> row
    for (const LockingBenchRow& r : rows)
        if (r.problem == "block") by[{r.element, r.n}][r.poisson] = &r;
    std::vector<std::string> out;
    for (const auto& [key, runs] : by) {
        const auto base = runs.find(0.3);
        if (base == runs.end() || runs.size() < 2) continue;
        const LockingBenchRow& a = *base->second;
        std::string line = fmt::format("block {} n {} ({} DOFs): error {:.3g} % at nu 0.3 (CG {}, {:.3g} s)", key.first,
                                       key.second, a.dofs, 100 * a.error, a.cg, a.cpu_s);
        for (const auto& [nu, b] : runs)
            if (nu != 0.3)
                line += fmt::format(", {:.3g} % at nu {} ({:.2f} x; CG {}, {:.3g} s)", 100 * b->error, nu,
                                    b->error / a.error, b->cg, b->cpu_s);
        out.push_back(line);
    }
    return out;
}

}  // namespace xcut
