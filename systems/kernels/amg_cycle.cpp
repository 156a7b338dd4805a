// The V-cycle of the smoothed-aggregation hierarchy (systems/kernels/amg.h): the finest level and
// the coarse levels with at least kTeamNonzeros on the calling OpenMP team, the rest on one thread
// of it.
#include <omp.h>

#include "engine/parallel.h"
#include "systems/kernels/amg.h"

namespace xcut {
namespace {

constexpr double kBoost = 1.1;      // the upper bound over the estimated lambda_max
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

/// A coarse level's operator: scalar rows of a single-precision CSR matrix. row(i, v, out): out[0] =
/// sum_j M_ij v(j), in four partial sums of a fixed order: a single running sum is one chain of
/// dependent multiply-adds (183 a row on the 53k-tet block's first coarse level, 253 in its
/// restriction), bound by the adder's latency, not by memory.
struct CsrRows {
    const CsrMatrixF& M;
    static constexpr int kWidth = 1;
    int groups() const { return static_cast<int>(M.rows()); }
    template <class V>
    void row(int i, V&& v, double* out) const {
        const int* col = M.innerIndexPtr();
        const float* val = M.valuePtr();
        const int end = M.outerIndexPtr()[i + 1];
        int k = M.outerIndexPtr()[i];
        double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
        for (; k + 4 <= end; k += 4) {
            s0 += double(val[k]) * v(col[k]), s1 += double(val[k + 1]) * v(col[k + 1]);
            s2 += double(val[k + 2]) * v(col[k + 2]), s3 += double(val[k + 3]) * v(col[k + 3]);
        }
        for (; k < end; ++k) s0 += double(val[k]) * v(col[k]);
        out[0] = (s0 + s1) + (s2 + s3);
    }
};

/// The finest level's operator: the step's block matrix with its blocks in single precision
/// (AmgHierarchy::finest), a node's three rows at once; the even and odd blocks in separate sums.
struct FinestRows {
    const LinearSystem& A;
    const std::vector<float>& value;
    static constexpr int kWidth = 3;
    int groups() const { return A.rows(); }
    template <class V>
    void row(int i, V&& v, double* out) const {
        double s[2][3] = {};
        for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b) {
            const float* m = value.data() + 9 * b;
            const int c = 3 * A.column[b];
            const double x0 = v(c), x1 = v(c + 1), x2 = v(c + 2);
            double* acc = s[b & 1];
            acc[0] += double(m[0]) * x0 + double(m[1]) * x1 + double(m[2]) * x2;
            acc[1] += double(m[3]) * x0 + double(m[4]) * x1 + double(m[5]) * x2;
            acc[2] += double(m[6]) * x0 + double(m[7]) * x1 + double(m[8]) * x2;
        }
        for (int k = 0; k < 3; ++k) out[k] = s[0][k] + s[1][k];
    }
};

/// body(i, Av_i) for every row i of level operator `op` applied to v(j), by `loop` over its groups.
template <class Loop, class Op, class V, class Body>
void rows_of(Loop loop, const Op& op, V&& v, Body&& body) {
    loop(op.groups(), [&](int g) {
        double out[Op::kWidth];
        op.row(g, v, out);
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
    const auto at = [](const Eigen::VectorXd& v) { return [&v](int j) { return v[j]; }; };
    // Pre-smoothing from x = 0: x1 = d1 = D^-1 b / theta, then x = x1 + c1 d1 + c2 D^-1 (b - A x1).
    rows_of(loop, op, [&](int j) { return dinv[j] * b[j] / theta; }, [&](int i, double t) {
        const double d1 = dinv[i] * b[i] / theta;
        d[i] = c1 * d1 + c2 * dinv[i] * (b[i] - t), x[i] = d1 + d[i];
    });
    rows_of(loop, op, at(x), [&](int i, double t) { r[i] = b[i] - t; });  // residual
    rows_of(loop, CsrRows{L.R}, at(r), [&](int i, double t) { C.b[i] = t; });
    coarse();
    rows_of(loop, CsrRows{L.P}, at(C.x), [&](int i, double t) { x[i] += t; });
    // Post-smoothing from the corrected x: y = x + D^-1 (b - A x) / theta, then x = y + d.
    rows_of(loop, op, at(x), [&](int i, double t) { d[i] = dinv[i] * (b[i] - t) / theta, y[i] = x[i] + d[i]; });
    rows_of(loop, op, at(y), [&](int i, double t) { d[i] = c1 * d[i] + c2 * dinv[i] * (b[i] - t), x[i] = y[i] + d[i]; });
}

/// The coarser levels from l on, on the calling thread: x_l = V-cycle(b_l).
void serial_cycle(AmgHierarchy& h, size_t l) {
    AmgLevel& L = h.levels[l];
    if (l + 1 == h.levels.size()) {
        L.x = h.coarsest.solve(L.b);
        return;
    }
    cycle(SerialLoop{}, CsrRows{L.A}, L, h.levels[l + 1], L.b, L.x, [&] { serial_cycle(h, l + 1); });
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
    cycle(TeamLoop{}, CsrRows{L.A}, L, h.levels[l + 1], L.b, L.x, [&] { team_cycle(h, l + 1); });
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
    cycle(TeamLoop{}, FinestRows{A, h.finest}, h.levels[0], h.levels[1], r, z, [&] { team_cycle(h, 1); });
}
}  // namespace xcut
