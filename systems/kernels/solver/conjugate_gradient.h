#pragma once
// Conjugate gradients for the implicit step (systems/solver/solver_system.h, systems/solver/linear_solver.h).
#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "engine/parallel.h"
#include "systems/kernels/solver/cg_result.h"

namespace xcut {

/// The vectors of a CG run: product q, residual r, preconditioned z, direction d.
struct CgWork {
    Eigen::VectorXd q, r, z, d;
    double bnorm = 0.0;  ///< |b| over the free entries
};

/// The start every CG here shares: |b| over the free entries, x projected onto them, q = A x. False
/// when there is nothing to iterate: b = 0 (x = 0, converged) or b not finite (NaN or inf forces: the
/// relative residual is NaN, which no caller accepts).
template <class Product>
bool cg_begin(Product&& apply, const Eigen::VectorXd& b, const Eigen::VectorXd& free_mask, Eigen::VectorXd& x,
              CgResult& result, CgWork& w) {
    const int n = static_cast<int>(b.size());
    w.bnorm = std::sqrt(deterministic_sums<1>(n, [&](int lo, int hi, auto& acc) {
        for (int i = lo; i < hi; ++i) acc[0] += b[i] * b[i] * free_mask[i];
    })[0]);
    x = x.cwiseProduct(free_mask);
    if (!std::isfinite(w.bnorm)) result.relative_residual = std::numeric_limits<double>::quiet_NaN();
    if (w.bnorm == 0.0) x.setZero();
    if (!std::isfinite(w.bnorm) || w.bnorm == 0.0) return false;
    w.q.resize(n), w.r.resize(n), w.z.resize(n), w.d.resize(n);
    apply(x, w.q);
    return true;
}

/// q projected onto the free entries, and d . q: the curvature of a search direction.
inline double project_dot(const Eigen::VectorXd& d, Eigen::VectorXd& q, const Eigen::VectorXd& free_mask) {
    return deterministic_sums<1>(static_cast<int>(d.size()), [&](int lo, int hi, auto& acc) {
        for (int i = lo; i < hi; ++i) {
            q[i] *= free_mask[i];
            acc[0] += d[i] * q[i];
        }
    })[0];
}

/// Preconditioned CG (Hestenes & Stiefel 1952; Saad, Iterative Methods, alg. 9.1) for the assembled
/// methods: `apply(p, out)` computes A p, `precondition(r, z)` z = M^-1 r. Held entries (mask 0) are
/// projected out of the residual and of z. Reductions in the fixed block order of
/// deterministic_sums: bit-identical for any thread count. Stops at |r| <= tol |b| or max_iterations.
template <class Product, class Preconditioner>
CgResult preconditioned_cg(Product&& apply, Preconditioner&& precondition, const Eigen::VectorXd& b,
                           const Eigen::VectorXd& free_mask, double tol, int max_iterations, Eigen::VectorXd& x) {
    const int n = static_cast<int>(b.size());
    CgResult result;
    CgWork work;
    if (!cg_begin(apply, b, free_mask, x, result, work)) return result;
    Eigen::VectorXd &q = work.q, &r = work.r, &z = work.z, &d = work.d;
    const double bnorm = work.bnorm;
    double rnorm = std::sqrt(deterministic_sums<1>(n, [&](int lo, int hi, auto& acc) {
        for (int i = lo; i < hi; ++i) {
            r[i] = free_mask[i] * (b[i] - q[i]);
            acc[0] += r[i] * r[i];
        }
    })[0]);
    auto precondition_dot = [&] {  // z = mask M^-1 r; returns r . z
        precondition(r, z);
        return deterministic_sums<1>(n, [&](int lo, int hi, auto& acc) {
            for (int i = lo; i < hi; ++i) {
                z[i] *= free_mask[i];
                acc[0] += r[i] * z[i];
            }
        })[0];
    };
    double rz = rnorm > tol * bnorm ? precondition_dot() : 0.0;
    d = z;
    while (rnorm > tol * bnorm && result.iterations < max_iterations && std::isfinite(rnorm)) {
        apply(d, q);
        const double dq = project_dot(d, q, free_mask);
        if (!(dq > 0.0)) break;  // zero or negative curvature: the matrix is not SPD here
        const double alpha = rz / dq;
        rnorm = std::sqrt(deterministic_sums<1>(n, [&](int lo, int hi, auto& acc) {
            for (int i = lo; i < hi; ++i) {
                x[i] += alpha * d[i];
                r[i] -= alpha * q[i];
                acc[0] += r[i] * r[i];
            }
        })[0]);
        ++result.iterations;
        if (!(rnorm > tol * bnorm)) break;
        const double rz_new = precondition_dot();
        const double beta = rz_new / rz;
        rz = rz_new;
        parallel_for(n, [&](int i) { d[i] = z[i] + beta * d[i]; });
    }
    result.relative_residual = rnorm / bnorm;
    return result;
}

/// Jacobi-preconditioned CG, matrix-free: `apply(p, out)` computes A p, `inv_diag` is diag(A)^-1 (the
/// paper's solver, and the reference the assembled methods are checked against).
template <class Product>
CgResult conjugate_gradient(Product&& apply, const Eigen::VectorXd& b, const Eigen::VectorXd& inv_diag,
                            const Eigen::VectorXd& free_mask, double tol, int max_iterations, Eigen::VectorXd& x) {
    const auto jacobi = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        z.resize(r.size());
        parallel_for(static_cast<int>(r.size()), [&](int i) { z[i] = r[i] * inv_diag[i]; });
    };
    return preconditioned_cg(apply, jacobi, b, free_mask, tol, max_iterations, x);
}

}  // namespace xcut
