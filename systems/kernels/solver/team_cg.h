#pragma once
// Preconditioned conjugate gradients for every linear method (systems/solver/linear_solver.h) with
// one synchronisation structure for the whole solve: a single OpenMP team, opened once per solve,
// runs every iteration, which is one product, one preconditioner application, one fused reduction
// and the vector updates, separated by barriers (three an iteration with the assembled product and
// a row-wise preconditioner; the matrix-free product adds its gather's). No parallel region is
// opened inside the iterations (docs/architecture.md, parallelism).
//
// The iteration is Chronopoulos & Gear's single-reduction form of PCG (Chronopoulos & Gear, "s-step
// iterative methods for symmetric linear systems", J. Comput. Appl. Math. 25, 1989; as written in
// Ghysels & Vanroose, "Hiding global synchronization latency in the preconditioned conjugate
// gradient algorithm", Parallel Computing 40, 2014, alg. 2): with u = M^-1 r and w = A u carried
// along, gamma = (r, u) and delta = (w, u) are summed in one pass, and s = A p is updated by
// recurrence, so an iteration needs one product and one reduction. In exact arithmetic it is PCG.
// |r|^2 is summed where the update makes r (no barrier of its own: the update's loop ends in
// one; the paper's form sums it with gamma and delta, after the preconditioner and the product),
// so the test for convergence comes before the preconditioner and the product, not after:
// a solve of k iterations applies the preconditioner k times, not k + 1 (for a Cholesky factor
// and the few iterations of a step, most of the solve).
//
// Reductions are summed in 64 fixed blocks of rows, each block by one thread, the block sums in
// order by every thread: bit-identical results for any thread count, no atomics. Held entries
// (mask 0) are projected out of r, u and w. Stops at |r| <= tol |b| or max_iterations.
#include <omp.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>

#include "engine/parallel.h"
#include "systems/kernels/solver/cg_result.h"

namespace xcut {

enum class Preconditioning { kRows, kSingle, kTeam };

namespace team_cg_detail {

constexpr int kBlocks = 64;

/// What the team shares: the vectors, and two sets of block sums used in turn (a thread may start
/// the next reduction while another still sums the last one; the one before it is past the barrier
/// between them).
struct Shared {
    int block_rows = 0, per = 0;
    Eigen::VectorXd r, u, w, p, s;
    std::array<std::array<std::array<double, 3>, kBlocks>, 2> partial{};
};

/// A row phase, called by every thread of the team: body(lo, hi, acc) over the 64 fixed blocks of
/// block rows (omp for: the barrier ends it). A reducing phase returns the block sums summed in
/// order, the same in every thread; `reductions` counts them (the same count in every thread).
template <class Body>
std::array<double, 3> rows(Shared& sh, int& reductions, Body&& body, bool reduce) {
    auto& sums = sh.partial[reductions % 2];
#pragma omp for schedule(static)
    for (int k = 0; k < kBlocks; ++k) {
        std::array<double, 3> acc{};
        const int lo = k * sh.per, hi = std::min(sh.block_rows, lo + sh.per);
        if (lo < hi) body(lo, hi, acc);
        if (reduce) sums[k] = acc;
    }
    std::array<double, 3> t{};
    if (!reduce) return t;
    ++reductions;
    for (const auto& q : sums)
        for (int k = 0; k < 3; ++k) t[k] += q[k];
    return t;
}

/// u = mask M^-1 r on the block rows [lo, hi), if the preconditioner is row-wise.
template <class PreconditionRows>
void precondition_rows(Preconditioning mode, PreconditionRows& precondition, const Eigen::VectorXd& mask, int lo, int hi,
                       const Eigen::VectorXd& r, Eigen::VectorXd& u) {
    if (mode != Preconditioning::kRows) return;
    precondition(lo, hi, r, u);
    for (int i = 3 * lo; i < 3 * hi; ++i) u[i] *= mask[i];
}

/// u = M^-1 r for a whole-vector preconditioner, called by every thread of the team: kTeam's
/// worksharing, or kSingle's one thread (the single's implicit barrier ends the step).
template <class PreconditionAll>
void precondition_whole(Preconditioning mode, PreconditionAll& precondition, const Eigen::VectorXd& r, Eigen::VectorXd& u) {
    if (mode == Preconditioning::kRows) return;
    if (mode == Preconditioning::kTeam) {
        precondition(r, u);
    } else {
#pragma omp single
        precondition(r, u);
    }
}

}  // namespace team_cg_detail

/// `product(v, out)`: out = A v, called by every thread of the team; its loops are worksharing
/// loops (`omp for`, a barrier at their end), so `out` is whole when it returns (out is sized).
/// The preconditioner, by `mode`: kRows, `precondition_rows(lo, hi, r, z)`: z = M^-1 r on the block
/// rows [lo, hi); kSingle, `precondition_all(r, z)` on the whole vector, run by one thread of the
/// team; kTeam, `precondition_all(r, z)` called by every thread, its loops worksharing (as product).
/// With kSingle and kTeam, z's held entries are projected out after the product A z, in its
/// reduction's loop (no loop and barrier of their own): `product` must not carry a held input entry
/// into a free row, as the assembled A does not (its held rows and columns are dropped,
/// filter_held_axes in systems/solver/linear_assembly.cpp).
/// The team has thread_count() threads from kParallelMin unknowns on, below it one (the barriers
/// cost more than the rows save), unless `heavy_preconditioner`: a kTeam preconditioner that does
/// enough work per application to pay for them (a Cholesky factor's split solves).
template <class Product, class PreconditionRows, class PreconditionAll>
CgResult team_cg(int block_rows, Product&& product, Preconditioning mode, PreconditionRows&& precondition_rows,
                 PreconditionAll&& precondition_all, const Eigen::VectorXd& b, const Eigen::VectorXd& mask, double tol,
                 int max_iterations, Eigen::VectorXd& x, bool heavy_preconditioner = false) {
    using team_cg_detail::rows;
    const int n = 3 * block_rows;
    team_cg_detail::Shared sh;
    sh.block_rows = block_rows, sh.per = (block_rows + team_cg_detail::kBlocks - 1) / team_cg_detail::kBlocks;
    sh.r.resize(n), sh.u.resize(n), sh.w.resize(n), sh.p.setZero(n), sh.s.setZero(n);
    Eigen::VectorXd &r = sh.r, &u = sh.u, &w = sh.w, &p = sh.p, &s = sh.s;
    CgResult result;
#pragma omp parallel num_threads(n >= kParallelMin || heavy_preconditioner ? thread_count() : 1)
    {
        int reductions = 0;
        const auto precondition = [&](int lo, int hi) {  // u = mask M^-1 r on rows, if row-wise
            team_cg_detail::precondition_rows(mode, precondition_rows, mask, lo, hi, r, u);
        };
        const auto precondition_whole = [&] {  // the same for a whole-vector preconditioner
            team_cg_detail::precondition_whole(mode, precondition_all, r, u);
        };
        // The start: x projected, r = mask (b - A x), u = mask M^-1 r, |b|.
        rows(sh, reductions, [&](int lo, int hi, auto&) {
            for (int i = 3 * lo; i < 3 * hi; ++i) x[i] *= mask[i];
        }, false);
        product(x, w);
        const std::array<double, 3> started = rows(sh, reductions, [&](int lo, int hi, auto& acc) {
            for (int i = 3 * lo; i < 3 * hi; ++i)
                r[i] = mask[i] * (b[i] - w[i]), acc[0] += mask[i] * b[i] * b[i], acc[2] += r[i] * r[i];
            precondition(lo, hi);
        }, true);
        const double bnorm = std::sqrt(started[0]);
        // |r|^2 in the same blocks and order as the fused reduction summed it before (the same
        // bits): k iterations apply the preconditioner k times, not k + 1 (header).
        const auto more = [&](double r2, int done) {
            return std::sqrt(r2) > tol * bnorm && done < max_iterations && std::isfinite(r2);
        };
        const bool start = std::isfinite(bnorm) && bnorm > 0.0;
        const bool iterate = start && more(started[2], 0);
        if (iterate) precondition_whole();
        // w = mask A u and the fused reduction: gamma = (r, u), delta = (w, u).
        const auto product_and_reduce = [&] {
            product(u, w);
            return rows(sh, reductions, [&](int lo, int hi, auto& acc) {
                for (int i = 3 * lo; i < 3 * hi; ++i) {
                    u[i] *= mask[i], w[i] *= mask[i];  // u's: a no-op for kRows (masked already)
                    acc[0] += r[i] * u[i], acc[1] += w[i] * u[i];
                }
            }, true);
        };
        // Plain scalars, no structured bindings: clang refuses a binding read in an OpenMP construct.
        const std::array<double, 3> first = iterate ? product_and_reduce() : std::array<double, 3>{};
        double gamma = first[0], rr = started[2];
        double alpha = gamma / first[1], beta = 0.0;
        int iterations = 0;
        while (iterate) {
            if (!(alpha > 0.0)) break;  // zero or negative curvature: the matrix is not SPD here
            rr = rows(sh, reductions, [&](int lo, int hi, auto& acc) {
                for (int i = 3 * lo; i < 3 * hi; ++i) {
                    p[i] = u[i] + beta * p[i], s[i] = w[i] + beta * s[i];
                    x[i] += alpha * p[i], r[i] -= alpha * s[i];
                    acc[2] += r[i] * r[i];
                }
                precondition(lo, hi);
            }, true)[2];
            ++iterations;
            if (!more(rr, iterations)) break;
            precondition_whole();
            const std::array<double, 3> next = product_and_reduce();  // gamma, delta
            beta = next[0] / gamma;
            alpha = next[0] / (next[1] - beta * next[0] / alpha);
            gamma = next[0];
        }
#pragma omp single
        {
            result.iterations = iterations;
            if (start) result.relative_residual = std::sqrt(rr) / bnorm;
            else if (bnorm == 0.0) x.setZero();  // b = 0: x = 0, converged
            else result.relative_residual = std::numeric_limits<double>::quiet_NaN();  // NaN or inf forces
        }
    }
    return result;
}

}  // namespace xcut
