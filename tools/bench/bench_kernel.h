#pragma once
// The force kernel against the machine's roofline (part of `xcut bench --suite perf`): the
// ForceSystem's measured time per step with its counted work and traffic per tetrahedron
// (tools/bench/force_kernel_model.h) give the achieved GFLOP/s and GB/s; the bound is
// min(peak, intensity x triad bandwidth) at the same thread count (tools/bench/roofline.h). The CG's
// matrix-free product, timed on its own, is measured the same way: it is most of a step.
#include <string>
#include <vector>

#include "tools/bench/bench.h"
#include "tools/bench/roofline.h"

namespace xcut {

struct KernelRow {
    std::string kernel;             ///< "force" (the ForceSystem, per step) or "cg_product" (K p, per CG iteration)
    int tets = 0, threads = 0;
    int kernel_threads = 0;         ///< threads its loops use: 1 below kParallelMin elements (engine/parallel.h)
    double ms = 0;                  ///< mean time of one call [ms]
    double newton_iterations = 0;   ///< polar decomposition, mean per tetrahedron (force only)
    double flops_per_element = 0, bytes_per_element = 0, intensity = 0;  ///< [flop], [byte], [flop/byte]
    double achieved_gflops = 0, achieved_gbs = 0;
    double peak_gflops = 0, triad_gbs = 0;  ///< the roofline at this thread count
    double bound_gflops = 0;                ///< min(peak, intensity x triad)
    std::string bound;                      ///< "compute" or "memory"
    double fraction = 0;                    ///< achieved / bound
};

/// Two rows (force, cg_product) per perf row whose kernel thread count the roofline has; the
/// bound is at that count.
std::vector<KernelRow> kernel_rows(const std::vector<PerfBenchRow>& rows, const std::vector<RooflinePoint>& roofline);

/// Measures the roofline at the suite's thread counts, then prints and writes
/// <csv stem>_roofline.csv and <csv stem>_kernel.csv.
void kernel_against_roofline(const std::vector<PerfBenchRow>& rows, const PerfBenchOptions& options);

}  // namespace xcut
