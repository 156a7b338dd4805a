#include "tools/bench/roofline.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <memory>

namespace xcut {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// K independent chains x_k <- x_k a + b; the inner loop is what the vectoriser turns into K / width
/// vector chains. With a < 1 and b = 1 - a the chains stay at 1 (no overflow, no denormals).
template <int K>
double chains(long iterations, double a, double b) {
    double x[K];
    for (int k = 0; k < K; ++k) x[k] = 1.0 + k * 1e-3;
    for (long i = 0; i < iterations; ++i)
        for (int k = 0; k < K; ++k) x[k] = x[k] * a + b;
    double s = 0.0;
    for (int k = 0; k < K; ++k) s += x[k];
    return s;
}

template <int K>
__attribute__((target("avx2,fma"))) double chains_fma(long iterations, double a, double b) {
    double x[K];
    for (int k = 0; k < K; ++k) x[k] = 1.0 + k * 1e-3;
    for (long i = 0; i < iterations; ++i)
        for (int k = 0; k < K; ++k) x[k] = __builtin_fma(x[k], a, b);
    double s = 0.0;
    for (int k = 0; k < K; ++k) s += x[k];
    return s;
}

/// GFLOP/s of `chain` (K chains) run by every thread at once; the best of `repeats` runs, so a
/// run in which the system let a thread wait does not lower the peak.
template <int K, class Chain>
double chain_gflops(int threads, long iterations, int repeats, Chain chain) {
    volatile double a = 0.9999999, b = 1e-7;  // opaque to the optimiser
    double best = 1e300, sink = 0.0;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(threads) reduction(+ : sink)
        sink += chain(iterations, a, b);
        best = std::min(best, seconds_since(t0));
    }
    volatile double keep = sink;
    (void)keep;
    return 2.0 * K * static_cast<double>(iterations) * threads / best * 1e-9;
}

}  // namespace

double triad_bandwidth_gbs(int threads, long n, int repeats) {
    std::unique_ptr<double[]> a(new double[n]), b(new double[n]), c(new double[n]);
    // First touch by the thread that will sweep each page (same static split as the sweep).
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long i = 0; i < n; ++i) a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
    const double s = 3.0;
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
        best = std::min(best, seconds_since(t0));
    }
    volatile double keep = a[n / 2];
    (void)keep;
    return 3.0 * sizeof(double) * static_cast<double>(n) / best * 1e-9;
}

double multiply_add_peak_gflops(int threads, long iterations, bool hardware_fma, int repeats) {
    // Enough chains to cover the add and multiply latencies on two pipes, few enough to stay in the
    // 16 vector registers; the best of two counts is reported (a peak is a maximum).
    if (hardware_fma) {
        if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return 0.0;
        return std::max(chain_gflops<32>(threads, iterations, repeats, chains_fma<32>),
                        chain_gflops<40>(threads, iterations, repeats, chains_fma<40>));
    }
    return std::max(chain_gflops<16>(threads, iterations, repeats, chains<16>),
                    chain_gflops<24>(threads, iterations, repeats, chains<24>));
}

std::vector<RooflinePoint> measure_roofline(const RooflineOptions& o, const std::vector<int>& threads) {
    std::vector<RooflinePoint> points;
    for (int t : threads) {
        RooflinePoint p;
        p.threads = t;
        p.triad_gbs = triad_bandwidth_gbs(t, o.triad_doubles, o.repeats);
        p.peak_gflops = multiply_add_peak_gflops(t, o.fma_iterations, false, o.repeats);
        p.fma_gflops = multiply_add_peak_gflops(t, o.fma_iterations, true, o.repeats);
        points.push_back(p);
    }
    return points;
}

std::string vector_isa() {
#if defined(__AVX512F__)
    std::string isa = "AVX-512 512-bit";
#elif defined(__AVX2__)
    std::string isa = "AVX2 256-bit";
#elif defined(__AVX__)
    std::string isa = "AVX 256-bit";
#elif defined(__SSE2__)
    std::string isa = "SSE2 128-bit";
#else
    std::string isa = "scalar";
#endif
#if defined(__FMA__)
    return isa + " with FMA";
#else
    return isa + " without FMA";
#endif
}

}  // namespace xcut
