#include "systems/kernels/solver/supernode_solve.h"

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

namespace xcut {
namespace {

/// The sums keep kLanes = 8 lanes (header), held as 8 / N native vectors of N lanes (GCC and Clang
/// vector extensions): N = 4 floats or 2 doubles in an SSE2 register for the portable kernels, 8 or
/// 4 in an AVX register for the AVX2 ones. Lane l is element l % N of part l / N whatever N is, so N
/// changes no bit. CMakeLists.txt builds this file alone with -Wno-psabi (the vectors never cross a
/// call) and -ffp-contract=off.
constexpr int kLanes = 8;
template <class Real, int N>
struct Native {
    typedef Real V __attribute__((vector_size(N * sizeof(Real))));
};
template <class Real, int N>
using Vec = typename Native<Real, N>::V;

/// Native lanes: SSE2's and AVX's.
template <class Real>
constexpr int kGenericLanes = 16 / sizeof(Real);
template <class Real>
constexpr int kAvx2Lanes = 32 / sizeof(Real);

/// Columns the solves take together: the block whose own rows are solved one by one, and whose
/// updates (forward) or sums (backward) over the rest of the supernode's rows share each load of the
/// vector. The block is the unit of the order the source fixes (header), the same in both kernels.
constexpr int kBlock = 4;

template <int N, class Real>
[[gnu::always_inline]] inline Vec<Real, N> load(const Real* p) {
    Vec<Real, N> v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <int N, class Real>
[[gnu::always_inline]] inline void store(Real* p, const Vec<Real, N>& v) {
    std::memcpy(p, &v, sizeof v);
}
template <int N, class Real>
[[gnu::always_inline]] inline Vec<Real, N> splat(Real s) {
    Vec<Real, N> v;
    for (int l = 0; l < N; ++l) v[l] = s;
    return v;
}

/// y[i] -= c[0][i] x[0], then c[1][i] x[1], ... (the W columns in order), for i in [0, n): each
/// entry on its own, so the same bits at any vector width. W is fixed at compile time so that the
/// vectors stay in registers.
template <int N, int W, class Real>
[[gnu::always_inline]] inline void update_rows(const Real* const* c, const Real* x, Real* y, int n) {
    Vec<Real, N> xv[W];
    for (int q = 0; q < W; ++q) xv[q] = splat<N>(x[q]);
    int i = 0;
    for (; i + N <= n; i += N) {
        Vec<Real, N> acc = load<N>(y + i);
        for (int q = 0; q < W; ++q) acc -= load<N>(c[q] + i) * xv[q];
        store<N>(y + i, acc);
    }
    for (; i < n; ++i) {
        Real acc = y[i];
        for (int q = 0; q < W; ++q) acc -= c[q][i] * x[q];
        y[i] = acc;
    }
}

/// out[q] = c[q] . b over [0, n) for W columns, each load of b shared by them: per column kLanes
/// partial sums (lane l: entries l, l + 8, ...), combined as in the header, then the entries past the
/// last whole eight added in order.
template <int N, int W, class Real>
[[gnu::always_inline]] inline void dots(const Real* const* c, const Real* b, int n, Real* out) {
    constexpr int parts = kLanes / N;
    Vec<Real, N> acc[W][parts] = {};
    int i = 0;
    for (; i + kLanes <= n; i += kLanes)
        for (int p = 0; p < parts; ++p) {
            const Vec<Real, N> bv = load<N>(b + i + p * N);
            for (int q = 0; q < W; ++q) acc[q][p] += load<N>(c[q] + i + p * N) * bv;
        }
    for (int q = 0; q < W; ++q) {
        Real l[kLanes];
        for (int k = 0; k < kLanes; ++k) l[k] = acc[q][k / N][k % N];
        Real s = ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]));
        for (int k = i; k < n; ++k) s += c[q][k] * b[k];
        out[q] = s;
    }
}

/// L w = b on the supernode's rows: w[0, cols) holds b's part on its columns and becomes x_s;
/// w[cols, rows) holds zeros and becomes -L21 x_s. Blocks of kBlock columns in order: the block's
/// own rows solved one by one (each pivot divides, then its column updates the block's rows below
/// it), then every row below the block updated by the block's columns in order (update_rows): each
/// entry of w meets its columns in increasing order, the column-by-column elimination's order.
template <int N, class Real>
[[gnu::always_inline]] inline void forward_body(const Real* L, int rows, int cols, Real* w) {
    const Real* c[kBlock];
    Real x[kBlock];
    for (int j = 0; j < cols; j += kBlock) {
        const int width = std::min(kBlock, cols - j), next = j + width;
        for (int q = 0; q < width; ++q) {
            c[q] = L + static_cast<std::ptrdiff_t>(j + q) * rows + next;
            const Real* column = L + static_cast<std::ptrdiff_t>(j + q) * rows;
            x[q] = w[j + q] /= column[j + q];
            for (int r = q + 1; r < width; ++r) w[j + r] -= column[j + r] * x[q];
        }
        if (width == kBlock) update_rows<N, kBlock>(c, x, w + next, rows - next);
        else
            for (int q = 0; q < width; ++q) update_rows<N, 1>(c + q, x + q, w + next, rows - next);
    }
}

/// L^T w = b on the supernode's rows: w[cols, rows) holds the solution below (final), w[0, cols)
/// b's part on its columns and becomes x_s. Blocks of kBlock columns from the last: each column's
/// sum over the rows below the block (dots, `pass` columns sharing each load), then the block's own
/// rows from its last column up, each column's entries there subtracted in increasing row order
/// after that sum, and the pivot divides.
template <int N, int pass, class Real>
[[gnu::always_inline]] inline void backward_body(const Real* L, int rows, int cols, Real* w) {
    const Real* c[kBlock];
    Real s[kBlock];
    for (int j = (cols - 1) / kBlock * kBlock; j >= 0; j -= kBlock) {
        const int width = std::min(kBlock, cols - j), next = j + width;
        for (int q = 0; q < width; ++q) c[q] = L + static_cast<std::ptrdiff_t>(j + q) * rows + next;
        if (width == kBlock)
            for (int q = 0; q < kBlock; q += pass) dots<N, pass>(c + q, w + next, rows - next, s + q);
        else
            for (int q = 0; q < width; ++q) dots<N, 1>(c + q, w + next, rows - next, s + q);
        for (int q = width - 1; q >= 0; --q) {
            const Real* column = L + static_cast<std::ptrdiff_t>(j + q) * rows;
            Real t = w[j + q] - s[q];
            for (int r = q + 1; r < width; ++r) t -= column[j + r] * w[j + r];
            w[j + q] = t / column[j + q];
        }
    }
}

template <class Real>
void forward_generic(const Real* L, int rows, int cols, Real* w) {
    forward_body<kGenericLanes<Real>>(L, rows, cols, w);
}
template <class Real>
void backward_generic(const Real* L, int rows, int cols, Real* w) {
    // Two double columns a pass: four would hold 16 SSE2 registers of sums alone.
    backward_body<kGenericLanes<Real>, sizeof(Real) == 4 ? kBlock : 2>(L, rows, cols, w);
}

#if defined(__x86_64__) || defined(__i386__)
#define XCUT_HAS_AVX2_KERNELS 1
template <class Real>
__attribute__((target("avx2"))) void forward_avx2(const Real* L, int rows, int cols, Real* w) {
    forward_body<kAvx2Lanes<Real>>(L, rows, cols, w);
}
template <class Real>
__attribute__((target("avx2"))) void backward_avx2(const Real* L, int rows, int cols, Real* w) {
    backward_body<kAvx2Lanes<Real>, kBlock>(L, rows, cols, w);
}
bool cpu_has_avx2() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2");
}
#else
bool cpu_has_avx2() { return false; }
#endif

}  // namespace

template <class Real>
const SupernodeKernels<Real>& supernode_kernels_generic() {
    static const SupernodeKernels<Real> kernels{forward_generic<Real>, backward_generic<Real>, "generic"};
    return kernels;
}

template <class Real>
const SupernodeKernels<Real>* supernode_kernels_avx2() {
#ifdef XCUT_HAS_AVX2_KERNELS
    static const SupernodeKernels<Real> kernels{forward_avx2<Real>, backward_avx2<Real>, "avx2"};
    static const bool available = cpu_has_avx2();
    return available ? &kernels : nullptr;
#else
    return nullptr;
#endif
}

template <class Real>
const SupernodeKernels<Real>& supernode_kernels_for(const char* setting) {
    const std::string wanted = setting ? setting : "";
    if (wanted == "generic") return supernode_kernels_generic<Real>();
    const SupernodeKernels<Real>* wide = supernode_kernels_avx2<Real>();
    if (wanted == "avx2" && !wide) throw std::invalid_argument("XCUT_KERNELS=avx2: this CPU has no AVX2");
    if (!wanted.empty() && wanted != "auto" && wanted != "avx2")
        throw std::invalid_argument("XCUT_KERNELS=" + wanted + ": expected \"auto\" (the default), \"generic\" or \"avx2\"");
    return wide ? *wide : supernode_kernels_generic<Real>();
}

template <class Real>
const SupernodeKernels<Real>& supernode_kernels() {
    static const SupernodeKernels<Real>& chosen = supernode_kernels_for<Real>(std::getenv("XCUT_KERNELS"));
    return chosen;
}

template const SupernodeKernels<float>& supernode_kernels_for<float>(const char*);
template const SupernodeKernels<double>& supernode_kernels_for<double>(const char*);
template const SupernodeKernels<float>& supernode_kernels<float>();
template const SupernodeKernels<double>& supernode_kernels<double>();
template const SupernodeKernels<float>& supernode_kernels_generic<float>();
template const SupernodeKernels<double>& supernode_kernels_generic<double>();
template const SupernodeKernels<float>* supernode_kernels_avx2<float>();
template const SupernodeKernels<double>* supernode_kernels_avx2<double>();

}  // namespace xcut
