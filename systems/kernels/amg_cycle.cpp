// The V-cycle of the smoothed-aggregation hierarchy (systems/kernels/amg.h): the finest level and
// the coarse levels with at least kTeamNonzeros on the calling OpenMP team, the rest on one thread
// of it.
#include <omp.h>

#include "engine/parallel.h"
#include "systems/kernels/amg.h"
#include "systems/linear_assembly.h"

namespace xcut {
namespace {

constexpr int kDegree = 2;          // Chebyshev degree before and after the coarse correction
constexpr double kBoost = 1.1;      // the upper bound over the estimated lambda_max
constexpr double kRatio = 30.0;     // the lower bound: upper / kRatio (Adams et al. 2003, §4)
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

/// x <- Chebyshev smoothing of A x = b (from x = 0 when `zero_start`), preconditioned by D^-1.
template <class Loop, class Apply>
void chebyshev(Loop loop, Apply&& apply, AmgLevel& L, const Eigen::VectorXd& b, Eigen::VectorXd& x, bool zero_start) {
    const double upper = kBoost * L.lambda_max, lower = upper / kRatio;
    const double theta = 0.5 * (upper + lower), delta = 0.5 * (upper - lower), sigma = theta / delta;
    const int n = static_cast<int>(b.size());
    const Eigen::VectorXd& dinv = L.inverse_diagonal;
    Eigen::VectorXd &d = L.d, &t = L.t;
    if (zero_start) {
        loop(n, [&](int i) { d[i] = dinv[i] * b[i] / theta, x[i] = d[i]; });
    } else {
        apply(x, t);
        loop(n, [&](int i) { d[i] = dinv[i] * (b[i] - t[i]) / theta, x[i] += d[i]; });
    }
    double rho = 1.0 / sigma;
    for (int k = 1; k < kDegree; ++k) {
        const double next = 1.0 / (2.0 * sigma - rho);
        const double c1 = next * rho, c2 = 2.0 * next / delta;
        apply(x, t);
        loop(n, [&](int i) { d[i] = c1 * d[i] + c2 * dinv[i] * (b[i] - t[i]), x[i] += d[i]; });
        rho = next;
    }
}

/// Row i of M v (single-precision M, double v and sum). Four partial sums in a fixed order: a
/// single running sum is one chain of dependent multiply-adds (183 a row on the 53k-tet block's
/// first coarse level, 253 in its restriction), bound by the adder's latency, not by memory.
inline double row_times(const CsrMatrixF& M, int i, const Eigen::VectorXd& v) {
    const int* col = M.innerIndexPtr();
    const float* val = M.valuePtr();
    const int end = M.outerIndexPtr()[i + 1];
    int k = M.outerIndexPtr()[i];
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    for (; k + 4 <= end; k += 4) {
        s0 += double(val[k]) * v[col[k]], s1 += double(val[k + 1]) * v[col[k + 1]];
        s2 += double(val[k + 2]) * v[col[k + 2]], s3 += double(val[k + 3]) * v[col[k + 3]];
    }
    for (; k < end; ++k) s0 += double(val[k]) * v[col[k]];
    return (s0 + s1) + (s2 + s3);
}

/// y = M v for a CSR matrix, rows by `loop`.
template <class Loop>
void multiply(Loop loop, const CsrMatrixF& M, const Eigen::VectorXd& v, Eigen::VectorXd& y) {
    loop(static_cast<int>(M.rows()), [&](int i) { y[i] = row_times(M, i, v); });
}

/// Block row i of y = A v, A's blocks in single precision (AmgHierarchy::finest); the even and
/// odd blocks in separate sums (two chains of multiply-adds per component, as row_times).
void multiply_finest(const LinearSystem& A, const std::vector<float>& value, int i, const Eigen::VectorXd& v,
                     Eigen::VectorXd& y) {
    double s[2][3] = {};
    for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b) {
        const float* m = value.data() + 9 * b;
        const double* x = v.data() + 3 * A.column[b];
        double* acc = s[b & 1];
        acc[0] += double(m[0]) * x[0] + double(m[1]) * x[1] + double(m[2]) * x[2];
        acc[1] += double(m[3]) * x[0] + double(m[4]) * x[1] + double(m[5]) * x[2];
        acc[2] += double(m[6]) * x[0] + double(m[7]) * x[1] + double(m[8]) * x[2];
    }
    for (int c = 0; c < 3; ++c) y[3 * i + c] = s[0][c] + s[1][c];
}

/// One V-cycle on level l with rhs b, result x, `coarse()` solving level l + 1 (its b set, its x
/// out). Smoothing, residual, restriction and prolongation run by `loop`.
template <class Loop, class Apply, class Coarse>
void cycle(Loop loop, Apply&& apply, AmgLevel& L, AmgLevel& C, const Eigen::VectorXd& b, Eigen::VectorXd& x,
           Coarse&& coarse) {
    const int n = static_cast<int>(b.size());
    chebyshev(loop, apply, L, b, x, true);
    apply(x, L.t);
    loop(n, [&](int i) { L.r[i] = b[i] - L.t[i]; });
    multiply(loop, L.R, L.r, C.b);
    coarse();
    loop(n, [&](int i) { x[i] += row_times(L.P, i, C.x); });
    chebyshev(loop, apply, L, b, x, false);
}

/// The coarser levels from l on, on the calling thread: x_l = V-cycle(b_l).
void serial_cycle(AmgHierarchy& h, size_t l) {
    AmgLevel& L = h.levels[l];
    if (l + 1 == h.levels.size()) {
        L.x = h.coarsest.solve(L.b);
        return;
    }
    const auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { multiply(SerialLoop{}, L.A, v, y); };
    cycle(SerialLoop{}, apply, L, h.levels[l + 1], L.b, L.x, [&] { serial_cycle(h, l + 1); });
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
    const auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { multiply(TeamLoop{}, L.A, v, y); };
    cycle(TeamLoop{}, apply, L, h.levels[l + 1], L.b, L.x, [&] { team_cycle(h, l + 1); });
}

}  // namespace

void amg_update_finest(AmgHierarchy& h, const LinearSystem& A) {
    AmgLevel& L = h.levels.front();
    h.finest.resize(A.value.size());
    parallel_for(A.rows(), [&](int i) {
        for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
            for (int k = 0; k < 9; ++k) h.finest[9 * b + k] = static_cast<float>(A.value[9 * b + k]);
        for (int c = 0; c < 3; ++c) L.inverse_diagonal[3 * i + c] = 1.0 / A.value[9 * A.diagonal[i] + 4 * c];
    });
}

void amg_cycle_in_team(AmgHierarchy& h, const LinearSystem& A, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    if (h.levels.size() == 1) {  // small enough to be solved exactly with the setup's matrix
#pragma omp single
        z = h.coarsest.solve(r);
        return;
    }
    const auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
#pragma omp for schedule(static)
        for (int i = 0; i < A.rows(); ++i) multiply_finest(A, h.finest, i, v, y);
    };
    cycle(TeamLoop{}, apply, h.levels[0], h.levels[1], r, z, [&] { team_cycle(h, 1); });
}
}  // namespace xcut
