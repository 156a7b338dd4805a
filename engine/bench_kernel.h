#pragma once
// The force kernel against the machine's roofline (part of `xcut bench --suite perf`): the
// ForceSystem's measured time per step with its counted work and traffic per tetrahedron
// (engine/force_kernel_model.h) give the achieved GFLOP/s and GB/s; the bound is
// min(peak, intensity x triad bandwidth) at the same thread count (engine/roofline.h).
#include <string>
#include <vector>

#include "engine/bench.h"
#include "engine/roofline.h"

namespace xcut {

struct KernelRow {
    int tets = 0, threads = 0;
    int kernel_threads = 0;         ///< threads its loops use: 1 below kParallelMin elements (engine/parallel.h)
    double force_ms = 0;            ///< ForceSystem, mean per step [ms]
    double newton_iterations = 0;   ///< polar decomposition, mean per tetrahedron
    double flops_per_element = 0, bytes_per_element = 0, intensity = 0;  ///< [flop], [byte], [flop/byte]
    double achieved_gflops = 0, achieved_gbs = 0;
    double peak_gflops = 0, triad_gbs = 0;  ///< the roofline at this thread count
    double bound_gflops = 0;                ///< min(peak, intensity x triad)
    std::string bound;                      ///< "compute" or "memory"
    double fraction = 0;                    ///< achieved / bound
};

/// One row per perf row whose kernel thread count the roofline has; the bound is at that count.
std::vector<KernelRow> kernel_rows(const std::vector<PerfBenchRow>& rows, const std::vector<RooflinePoint>& roofline);

/// Measures the roofline at the suite's thread counts, then prints and writes
/// <csv stem>_roofline.csv and <csv stem>_kernel.csv.
void kernel_against_roofline(const std::vector<PerfBenchRow>& rows, const PerfBenchOptions& options);

}  // namespace xcut
