#pragma once
// The machine's roofline, measured by the binary that runs the engine (`xcut bench --suite perf`):
// a STREAM-like triad for the memory bandwidth and independent multiply-add chains for the
// floating-point peak, both compiled with the flags the engine is compiled with, so the bound a
// kernel is compared against is what this build can reach, not a datasheet figure.
#include <string>
#include <vector>

namespace xcut {

struct RooflineOptions {
    long triad_doubles = 1L << 24;  ///< elements per triad array: 3 x 128 MiB, far above any L3
    int repeats = 5;                ///< best of this many runs of each (STREAM's convention)
    long fma_iterations = 20'000'000;  ///< chain steps per thread, run and chain count tried
};

struct RooflinePoint {
    int threads = 0;
    double triad_gbs = 0;     ///< a[i] = b[i] + s c[i]: 24 bytes per i (read 2, write 1; no write-allocate counted) [GB/s]
    double peak_gflops = 0;   ///< multiply-add chains as this build vectorises them (see vector_isa()) [GFLOP/s]
    double fma_gflops = 0;    ///< the same chains with the hardware's FMA instruction (AVX2 + FMA); 0 if absent
};

/// Best triad bandwidth over `repeats` sweeps of three arrays of n doubles on `threads` threads [GB/s].
double triad_bandwidth_gbs(int threads, long n, int repeats);
/// Multiply-add peak on `threads` threads: every thread runs independent chains x = x a + b
/// (2 flops per step), best over a few chain counts and `repeats` runs [GFLOP/s]. `hardware_fma`:
/// the same loop built for AVX2 + FMA (a reference for what a -march=native build would reach);
/// 0 if the CPU lacks it.
double multiply_add_peak_gflops(int threads, long iterations, bool hardware_fma, int repeats = 3);
/// Both, for each thread count.
std::vector<RooflinePoint> measure_roofline(const RooflineOptions& options, const std::vector<int>& threads);
/// The vector instruction set this build compiles to (from the compiler's predefined macros),
/// e.g. "SSE2 128-bit without FMA" (no commas: it is written into CSV cells).
std::string vector_isa();

}  // namespace xcut
