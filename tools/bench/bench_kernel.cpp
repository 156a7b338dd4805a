#include "tools/bench/bench_kernel.h"

#include <algorithm>
#include <fmt/format.h>

#include "tools/bench/force_kernel_model.h"
#include "engine/io/output.h"
#include "engine/parallel.h"

namespace xcut {

namespace {

KernelRow against_roofline(const char* kernel, const PerfBenchRow& r, double ms, const ForceKernelCounts& c,
                           const RooflinePoint& point) {
    KernelRow k;
    k.kernel = kernel;
    k.tets = r.tets;
    k.threads = r.threads;
    k.kernel_threads = point.threads;
    k.ms = ms;
    k.flops_per_element = c.flops_per_element;
    k.bytes_per_element = c.bytes_per_element;
    k.intensity = c.intensity();
    const double per_second = r.tets / (ms * 1e-3);  // elements per second
    k.achieved_gflops = c.flops_per_element * per_second * 1e-9;
    k.achieved_gbs = c.bytes_per_element * per_second * 1e-9;
    k.peak_gflops = point.peak_gflops;
    k.triad_gbs = point.triad_gbs;
    const double memory_bound = k.intensity * k.triad_gbs;
    k.bound_gflops = std::min(k.peak_gflops, memory_bound);
    k.bound = memory_bound < k.peak_gflops ? "memory" : "compute";
    k.fraction = k.achieved_gflops / k.bound_gflops;
    return k;
}

}  // namespace

std::vector<KernelRow> kernel_rows(const std::vector<PerfBenchRow>& rows, const std::vector<RooflinePoint>& roofline) {
    std::vector<KernelRow> out;
    for (const PerfBenchRow& r : rows) {
        // The element loops of a mesh below kParallelMin tetrahedra run on one thread whatever the setting.
        const int used = r.tets < kParallelMin ? 1 : r.threads;
        const auto point = std::find_if(roofline.begin(), roofline.end(),
                                        [&](const RooflinePoint& p) { return p.threads == used; });
        if (point == roofline.end()) continue;
        const double ratio = static_cast<double>(r.nodes) / r.tets;
        if (r.force_ms > 0.0) {
            out.push_back(against_roofline("force", r, r.force_ms, force_system_counts(r.newton_iterations, ratio), *point));
            out.back().newton_iterations = r.newton_iterations;
        }
        if (r.product_ms > 0.0)
            out.push_back(against_roofline("cg_product", r, r.product_ms, stiffness_product_counts(ratio), *point));
    }
    return out;
}

void kernel_against_roofline(const std::vector<PerfBenchRow>& rows, const PerfBenchOptions& o) {
    std::vector<RooflinePoint> roofline;
    ProgressBar bar("roofline", static_cast<int>(o.threads.size()));
    for (int t : o.threads) {
        roofline.push_back(measure_roofline(o.roofline, {t}).front());
        bar.update(static_cast<int>(roofline.size()));
    }
    bar.finish();
    const double triad_mib = 3.0 * 8.0 * static_cast<double>(o.roofline.triad_doubles) / (1 << 20);
    fmt::print("\nroofline (this build: {}; triad over 3 x {:.0f} MiB, best of {})\n", vector_isa(), triad_mib / 3.0,
               o.roofline.repeats);
    auto csv = open_csv(sibling_csv(o.csv, "roofline"));
    csv.print("threads,triad_gbs,peak_gflops,fma_gflops,triad_mib,vector_isa\n");
    for (const RooflinePoint& p : roofline) {
        fmt::print("  {} thread{}: triad {:.1f} GB/s; multiply-add peak {:.1f} GFLOP/s as built, {:.1f} with AVX2 + FMA\n",
                   p.threads, p.threads == 1 ? " " : "s", p.triad_gbs, p.peak_gflops, p.fma_gflops);
        csv.print("{},{:.3f},{:.3f},{:.3f},{:.0f},{}\n", p.threads, p.triad_gbs, p.peak_gflops, p.fma_gflops, triad_mib,
                  vector_isa());
    }

    auto kcsv = open_csv(sibling_csv(o.csv, "kernel"));
    kcsv.print("kernel,tets,threads,kernel_threads,ms,newton_iterations,flops_per_element,bytes_per_element,intensity,achieved_gflops,"
               "achieved_gbs,peak_gflops,triad_gbs,bound_gflops,bound,fraction_of_bound\n");
    fmt::print("\nkernels against the roofline: force = the ForceSystem (rotations, forces, stiffness diagonal, "
               "gathers), per step; cg_product = the CG's K p, per iteration\n");
    fmt::print("{:>10} {:>8} {:>7} {:>4} {:>9} {:>7} {:>8} {:>7} {:>6} {:>8} {:>7} {:>8} {:>8} {:>8}\n", "kernel", "tets",
               "threads", "used", "ms",
               "Newton", "flop/el", "B/el", "AI", "GFLOP/s", "GB/s", "bound", "bound by", "achieved");
    for (const KernelRow& k : kernel_rows(rows, roofline)) {
        fmt::print("{:>10} {:>8} {:>7} {:>4} {:>9.3f} {:>7.2f} {:>8.0f} {:>7.0f} {:>6.2f} {:>8.2f} {:>7.2f} {:>8.1f} {:>8} {:>7.1f}%\n",
                   k.kernel, k.tets, k.threads, k.kernel_threads, k.ms, k.newton_iterations, k.flops_per_element, k.bytes_per_element,
                   k.intensity, k.achieved_gflops, k.achieved_gbs, k.bound_gflops, k.bound, 100.0 * k.fraction);
        kcsv.print("{},{},{},{},{:.5f},{:.3f},{:.1f},{:.1f},{:.4f},{:.4f},{:.4f},{:.3f},{:.3f},{:.3f},{},{:.4f}\n", k.kernel,
                   k.tets, k.threads, k.kernel_threads, k.ms, k.newton_iterations, k.flops_per_element, k.bytes_per_element, k.intensity,
                   k.achieved_gflops, k.achieved_gbs, k.peak_gflops, k.triad_gbs, k.bound_gflops, k.bound, k.fraction);
    }
    fmt::print("target: the force kernel at >= 50% of the roofline it is bound by\n");
}

}  // namespace xcut
