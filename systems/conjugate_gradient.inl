#pragma once
#include <cmath>

#include "engine/parallel.h"

namespace xcut {

template <class Product>
CgResult conjugate_gradient(Product&& apply, const Eigen::VectorXd& b, const Eigen::VectorXd& inv_diag,
                            const Eigen::VectorXd& free_mask, double tol, int max_iterations,
                            Eigen::VectorXd& x) {
    const int n = static_cast<int>(b.size());
    CgResult result;
    const Eigen::VectorXd bf = b.cwiseProduct(free_mask);
    const double bnorm = std::sqrt(deterministic_dot(bf, bf));
    x = x.cwiseProduct(free_mask);
    if (bnorm == 0.0) {
        x.setZero();
        return result;
    }
    Eigen::VectorXd q(n), r(n), z(n), d(n);
    apply(x, q);
    r = bf - q.cwiseProduct(free_mask);
    z = r.cwiseProduct(inv_diag);
    d = z;
    double rz = deterministic_dot(r, z);
    double rnorm = std::sqrt(deterministic_dot(r, r));
    while (rnorm > tol * bnorm && result.iterations < max_iterations) {
        apply(d, q);
        q = q.cwiseProduct(free_mask);
        const double dq = deterministic_dot(d, q);
        if (!(dq > 0.0)) break;  // direction of zero curvature: nothing more to gain
        const double alpha = rz / dq;
        x += alpha * d;
        r -= alpha * q;
        ++result.iterations;
        rnorm = std::sqrt(deterministic_dot(r, r));
        z = r.cwiseProduct(inv_diag);
        const double rz_next = deterministic_dot(r, z);
        d = z + (rz_next / rz) * d;
        rz = rz_next;
    }
    result.relative_residual = rnorm / bnorm;
    return result;
}

}  // namespace xcut
