#pragma once
// A thin OpenMP layer. Work is split statically, and every reduction is summed in a fixed order of
// fixed-size blocks, so a result never depends on how many threads ran it (bit-identical for 1 and 2
// threads). No floating-point atomics anywhere.
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>

namespace xcut {

/// Number of threads systems use; set once from --threads (default 2). thread_count() is the count
/// a team takes now: one fewer while a background job runs (engine/background_threads.h);
/// configured_thread_count() the count set, for what reports or restores the setting.
void set_thread_count(int threads);
int thread_count();
int configured_thread_count();

/// Wall-clock time [s] on the steady clock (for delays and timings, never for results).
double wall_seconds();

/// Items below which a loop runs serially: forking costs more than it saves.
constexpr int kParallelMin = 8192;

/// Calls body(i) for i in [0, count), split statically over the threads. Below min_parallel items
/// the loop runs serially.
template <class Body>
inline void parallel_for(int count, Body&& body, int min_parallel = kParallelMin) {
    if (count < min_parallel || thread_count() == 1) {
        for (int i = 0; i < count; ++i) body(i);
        return;
    }
#pragma omp parallel for schedule(static) num_threads(thread_count())
    for (int i = 0; i < count; ++i) body(i);
}

/// Calls body(i) for i in [0, count) when the items cost unevenly and each is large (a zone
/// element's quadrature: thousands of points beside a few dozen): handed to the threads one at a
/// time as they come free. Each body(i) writes only its own results, so they do not depend on
/// which thread ran it; body must not throw.
template <class Body>
inline void parallel_for_uneven(int count, Body&& body) {
    if (count < 2 || thread_count() == 1) {
        for (int i = 0; i < count; ++i) body(i);
        return;
    }
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
    for (int i = 0; i < count; ++i) body(i);
}

/// parallel_for_uneven with a scratch object per thread, made once by make() on each thread that
/// runs items (a sparse solve's work vectors): body(i, scratch). The same rule: each body(i) writes
/// only its own results and leaves the scratch as it found it.
template <class Make, class Body>
inline void parallel_for_uneven_scratch(int count, Make&& make, Body&& body) {
    if (count < 2 || thread_count() == 1) {
        auto scratch = make();
        for (int i = 0; i < count; ++i) body(i, scratch);
        return;
    }
#pragma omp parallel num_threads(thread_count())
    {
        auto scratch = make();
#pragma omp for schedule(dynamic, 1)
        for (int i = 0; i < count; ++i) body(i, scratch);
    }
}

/// Sum of term(i) over [0, count) in a fixed association order: 64 blocks, each summed serially,
/// then the block sums summed serially. Independent of the thread count.
template <class Term>
inline double deterministic_sum(int count, Term&& term) {
    constexpr int kBlocks = 64;
    std::array<double, kBlocks> partial{};
    const int per = (count + kBlocks - 1) / kBlocks;
    parallel_for(
        kBlocks,
        [&](int b) {
            const int lo = b * per, hi = std::min(count, lo + per);
            double s = 0.0;
            for (int i = lo; i < hi; ++i) s += term(i);
            partial[b] = s;
        },
        count >= kParallelMin ? 1 : kBlocks + 1);
    double total = 0.0;
    for (double p : partial) total += p;
    return total;
}

/// K sums at once over [0, count): body(lo, hi, acc) adds its terms for [lo, hi) into acc[0..K).
/// Same fixed 64-block association as deterministic_sum, so fused loops stay thread-independent.
template <int K, class Body>
inline std::array<double, K> deterministic_sums(int count, Body&& body) {
    constexpr int kBlocks = 64;
    std::array<std::array<double, K>, kBlocks> partial{};
    const int per = (count + kBlocks - 1) / kBlocks;
    parallel_for(
        kBlocks,
        [&](int b) {
            const int lo = b * per, hi = std::min(count, lo + per);
            std::array<double, K> acc{};
            if (lo < hi) body(lo, hi, acc);
            partial[b] = acc;
        },
        count >= kParallelMin ? 1 : kBlocks + 1);
    std::array<double, K> total{};
    for (const auto& p : partial)
        for (int k = 0; k < K; ++k) total[k] += p[k];
    return total;
}

inline double deterministic_dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return deterministic_sum(static_cast<int>(a.size()), [&](int i) { return a[i] * b[i]; });
}

}  // namespace xcut
