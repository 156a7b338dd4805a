// The V-cycle of the smoothed-aggregation hierarchy (systems/kernels/solver/amg.h): the finest level and
// the coarse levels with at least kTeamNonzeros on the calling OpenMP team, the rest on one thread
// of it.
#include <omp.h>

#include "engine/parallel.h"
#include "systems/kernels/solver/amg.h"

namespace xcut {
namespace {

constexpr double kBoost = 1.1;  // the upper bound over the estimated lambda_max
// The lower bound: upper / kRatio. Adams et al. 2003 (§4) take 30; 15 smooths more of the middle of
// the spectrum and took CG from 8.45 to 7.95 iterations a step on the 53k-tet block, 9.10 to 7.85
// on the default scene and 27.2 to 26.6 on the thin membrane (9.51 and 9.46 on hand_dorsum).
constexpr double kRatio = 15.0;
constexpr long kTeamNonzeros = 50000;  // a coarse level with fewer runs on one thread

/// Loops of the levels the team shares: worksharing (a barrier at the end of each).
struct TeamLoop {
    template <class Body>
    void operator()(int n, Body&& body) const {
#pragma omp for schedule(static)
        for (int i = 0; i < n; ++i) body(i);
    }
};
/// Loops of the small coarse levels: on the calling thread.
struct SerialLoop {
    template <class Body>
    void operator()(int n, Body&& body) const {
        for (int i = 0; i < n; ++i) body(i);
    }
};

/// Four doubles in one register (two SSE2 halves in the portable build, one AVX register with
/// XCUT_AVX2); GCC and Clang vector extensions (CMakeLists.txt: -Wno-psabi for this file).
typedef double Double4 __attribute__((vector_size(32)));
typedef float Float4 __attribute__((vector_size(16)));

/// The four floats at p, widened.
inline Double4 widened(const float* p) {
    Float4 f;
    __builtin_memcpy(&f, p, sizeof f);
    return __builtin_convertvector(f, Double4);
}
inline Double4 loaded(const double* p) {
    Double4 d;
    __builtin_memcpy(&d, p, sizeof d);
    return d;
}
inline double lane_sum(const Double4& v) { return (v[0] + v[1]) + (v[2] + v[3]); }

/// Each level operator below comes in two kinds: kScaled = false gives rows of M v; kScaled = true
/// rows of M (D^-1 v), D^-1 applied as v is read: the first smoothing step's product, without a
/// loop (and a barrier) of its own to form D^-1 b. scaled(op, D^-1) makes the second from the first.

/// A coarse level's operator (RunMatrix): row(i, v, out): out[0] = sum_j M_ij v[j], each run four
/// entries at a time in two vector sums of a fixed order. A run's last 1-3 entries are taken with
/// the four that end the run, the lanes already summed weighted by 0. A single running sum a row
/// was one chain of dependent multiply-adds (183 a row on the 53k-tet block's first coarse level,
/// 253 in its restriction), bound by the adder's latency, not by memory.
template <bool kScaled>
struct RunRowsOf {
    const RunMatrix& M;
    const double* inverse_diagonal = nullptr;  ///< D^-1, with kScaled
    static constexpr int kWidth = 1;
    int groups() const { return M.rows(); }
    void row(int i, const double* v, double* out) const {
        static constexpr Double4 kLast[4] = {{0, 0, 0, 0}, {0, 0, 0, 1}, {0, 0, 1, 1}, {0, 1, 1, 1}};
        Double4 s0 = {}, s1 = {};
        double rest = 0.0;
        for (int k = M.row_start[i]; k < M.row_start[i + 1]; ++k) {
            const float* a = M.value.data() + M.run_start[k];
            const int column = M.run_column[k], n = M.run_start[k + 1] - M.run_start[k];
            const double* x = v + column;
            const auto at = [&](int j) {  // four entries of v (of D^-1 v) from j
                if constexpr (kScaled) return loaded(x + j) * loaded(inverse_diagonal + column + j);
                return loaded(x + j);
            };
            int j = 0;
            for (; j + 8 <= n; j += 8) s0 += widened(a + j) * at(j), s1 += widened(a + j + 4) * at(j + 4);
            if (j + 4 <= n) s0 += widened(a + j) * at(j), j += 4;
            if (j == n) continue;
            if (n >= 4)
                s1 += widened(a + n - 4) * at(n - 4) * kLast[n - j];
            else
                for (; j < n; ++j) rest += double(a[j]) * (kScaled ? x[j] * inverse_diagonal[column + j] : x[j]);
        }
        out[0] = lane_sum(s0 + s1) + rest;
    }
};

/// The finest level's operator: the step's block matrix with its blocks in single precision and
/// column-major (AmgHierarchy::finest), a node's three rows at once as sum_k column_k v_k in one
/// vector of four (lane 3 holds the next column's first entry times v_k and is dropped); a row's
/// even and odd blocks in separate sums. Scalar rows with a float-to-double conversion per entry
/// ran a product in 0.29-0.41 ms on the 53k-tet block; this runs it in 0.17-0.22 (2 threads), where
/// the double product runs in 0.18-0.26.
template <bool kScaled>
struct FinestRowsOf {
    const LinearSystem& A;
    const std::vector<float>& value;
    const double* inverse_diagonal = nullptr;  ///< D^-1, with kScaled
    static constexpr int kWidth = 3;
    int groups() const { return A.rows(); }
    void row(int i, const double* v, double* out) const {
        const auto block = [&](int b) {
            const float* m = value.data() + 9 * b;
            const int c = 3 * A.column[b];
            const double* x = v + c;
            if constexpr (kScaled) {
                const double* s = inverse_diagonal + c;
                return widened(m) * (x[0] * s[0]) + widened(m + 3) * (x[1] * s[1]) +
                       widened(m + 6) * (x[2] * s[2]);
            }
            return widened(m) * x[0] + widened(m + 3) * x[1] + widened(m + 6) * x[2];
        };
        Double4 even = {}, odd = {};  // two named sums stay in registers (an indexed pair did not)
        const int end = A.row_offset[i + 1];
        int b = A.row_offset[i];
        for (; b + 2 <= end; b += 2) even += block(b), odd += block(b + 1);
        if (b < end) even += block(b);
        const Double4 sum = even + odd;
        for (int k = 0; k < 3; ++k) out[k] = sum[k];
    }
};

using RunRows = RunRowsOf<false>;
using FinestRows = FinestRowsOf<false>;
inline RunRowsOf<true> scaled(const RunRows& op, const double* inverse_diagonal) { return {op.M, inverse_diagonal}; }
inline FinestRowsOf<true> scaled(const FinestRows& op, const double* inverse_diagonal) {
    return {op.A, op.value, inverse_diagonal};
}

/// body(i, (M v)_i) for every row i of level operator `op` (M), by `loop` over its groups.
template <class Loop, class Op, class Body>
void rows_of(Loop loop, const Op& op, const Eigen::VectorXd& v, Body&& body) {
    loop(op.groups(), [&](int g) {
        double out[Op::kWidth];
        op.row(g, v.data(), out);
        for (int k = 0; k < Op::kWidth; ++k) body(Op::kWidth * g + k, out[k]);
    });
}

/// One V-cycle on level L with rhs b, result x, `coarse()` solving level C (its b set, its x out).
/// Chebyshev smoothing of degree 2 preconditioned by D^-1 before and after, on
/// [lambda_max / kRatio, kBoost lambda_max] (Adams et al. 2003): each smoothing step's product and
/// update are one row loop (the update written to the other of x and L.t, since other rows still
/// read the old values), and the residual's product and difference another, so a level costs six
/// loops, six barriers of the team.
template <class Loop, class Op, class Coarse>
void cycle(Loop loop, const Op& op, AmgLevel& L, AmgLevel& C, const Eigen::VectorXd& b, Eigen::VectorXd& x,
           Coarse&& coarse) {
    const double upper = kBoost * L.lambda_max, lower = upper / kRatio;
    const double theta = 0.5 * (upper + lower), delta = 0.5 * (upper - lower), sigma = theta / delta;
    const double rho = 1.0 / sigma, next = 1.0 / (2.0 * sigma - rho);
    const double c1 = next * rho, c2 = 2.0 * next / delta;  // the second step's coefficients
    const Eigen::VectorXd& dinv = L.inverse_diagonal;
    Eigen::VectorXd &d = L.d, &y = L.t, &r = L.r;
    // Pre-smoothing from x = 0: x1 = d1 = D^-1 b / theta, then x = x1 + c1 d1 + c2 D^-1 (b - A x1),
    // with A x1 = (A D^-1 b) / theta.
    rows_of(loop, scaled(op, dinv.data()), b, [&](int i, double t) {
        const double d1 = dinv[i] * b[i] / theta;
        d[i] = c1 * d1 + c2 * dinv[i] * (b[i] - t / theta), x[i] = d1 + d[i];
    });
    rows_of(loop, op, x, [&](int i, double t) { r[i] = b[i] - t; });  // residual
    rows_of(loop, RunRows{L.R}, r, [&](int i, double t) { C.b[i] = t; });
    coarse();
    rows_of(loop, RunRows{L.P}, C.x, [&](int i, double t) { x[i] += t; });
    // Post-smoothing from the corrected x: y = x + D^-1 (b - A x) / theta, then x = y + d.
    rows_of(loop, op, x, [&](int i, double t) { d[i] = dinv[i] * (b[i] - t) / theta, y[i] = x[i] + d[i]; });
    rows_of(loop, op, y,
            [&](int i, double t) { d[i] = c1 * d[i] + c2 * dinv[i] * (b[i] - t), x[i] = y[i] + d[i]; });
}

/// The coarser levels from l on, on the calling thread: x_l = V-cycle(b_l).
void serial_cycle(AmgHierarchy& h, size_t l) {
    AmgLevel& L = h.levels[l];
    if (l + 1 == h.levels.size()) {
        L.x = h.coarsest.solve(L.b);
        return;
    }
    cycle(SerialLoop{}, RunRows{L.A}, L, h.levels[l + 1], L.b, L.x, [&] { serial_cycle(h, l + 1); });
}

/// Level l on (l >= 1) by the team while its matrix is large enough to share (kTeamNonzeros),
/// then on one thread of it.
void team_cycle(AmgHierarchy& h, size_t l) {
    AmgLevel& L = h.levels[l];
    if (l + 1 == h.levels.size() || L.A.nonZeros() < kTeamNonzeros) {
#pragma omp single
        serial_cycle(h, l);
        return;
    }
    cycle(TeamLoop{}, RunRows{L.A}, L, h.levels[l + 1], L.b, L.x, [&] { team_cycle(h, l + 1); });
}

}  // namespace

void run_product(const RunMatrix& M, const Eigen::VectorXd& v, Eigen::VectorXd& y) {
    y.resize(M.rows());
    rows_of(SerialLoop{}, RunRows{M}, v, [&](int i, double t) { y[i] = t; });
}

void amg_update_finest(AmgHierarchy& h, const LinearSystem& A) {
    AmgLevel& L = h.levels.front();
    h.finest.resize(A.value.size() + 1);  // + 1: the last column's four-wide load (FinestRows)
    parallel_for(A.rows(), [&](int i) {
        for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    h.finest[9 * b + 3 * c + r] = static_cast<float>(A.value[9 * b + 3 * r + c]);
        for (int c = 0; c < 3; ++c) L.inverse_diagonal[3 * i + c] = 1.0 / A.value[9 * A.diagonal[i] + 4 * c];
    });
}

void amg_cycle_in_team(AmgHierarchy& h, const LinearSystem& A, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    if (h.levels.size() == 1) {  // small enough to be solved exactly with the setup's matrix
#pragma omp single
        z = h.coarsest.solve(r);
        return;
    }
    cycle(TeamLoop{}, FinestRows{A, h.finest}, h.levels[0], h.levels[1], r, z, [&] { team_cycle(h, 1); });
}
}  // namespace xcut
