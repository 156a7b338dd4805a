#pragma once
#include <cmath>

#include "engine/parallel.h"

namespace xcut {

template <class Product>
CgResult conjugate_gradient(Product&& apply, const Eigen::VectorXd& b, const Eigen::VectorXd& inv_diag,
                            const Eigen::VectorXd& free_mask, double tol, int max_iterations,
                            Eigen::VectorXd& x) {
    // Vector updates are fused into a few parallel passes; every reduction goes through the fixed
    // block order of deterministic_sums, so iterates are bit-identical for any thread count.
    const int n = static_cast<int>(b.size());
    CgResult result;
    Eigen::VectorXd q(n), r(n), z(n), d(n);
    const double bb = deterministic_sums<1>(n, [&](int lo, int hi, auto& acc) {
        for (int i = lo; i < hi; ++i) acc[0] += b[i] * b[i] * free_mask[i];
    })[0];
    const double bnorm = std::sqrt(bb);
    x = x.cwiseProduct(free_mask);
    if (bnorm == 0.0) {
        x.setZero();
        return result;
    }
    apply(x, q);
    auto sums = deterministic_sums<2>(n, [&](int lo, int hi, auto& acc) {
        for (int i = lo; i < hi; ++i) {
            r[i] = free_mask[i] * (b[i] - q[i]);
            z[i] = r[i] * inv_diag[i];
            d[i] = z[i];
            acc[0] += r[i] * z[i];
            acc[1] += r[i] * r[i];
        }
    });
    double rz = sums[0], rnorm = std::sqrt(sums[1]);
    while (rnorm > tol * bnorm && result.iterations < max_iterations) {
        apply(d, q);
        const double dq = deterministic_sums<1>(n, [&](int lo, int hi, auto& acc) {
            for (int i = lo; i < hi; ++i) {
                q[i] *= free_mask[i];
                acc[0] += d[i] * q[i];
            }
        })[0];
        if (!(dq > 0.0)) break;  // direction of zero curvature: nothing more to gain
        const double alpha = rz / dq;
        sums = deterministic_sums<2>(n, [&](int lo, int hi, auto& acc) {
            for (int i = lo; i < hi; ++i) {
                x[i] += alpha * d[i];
                r[i] -= alpha * q[i];
                z[i] = r[i] * inv_diag[i];
                acc[0] += r[i] * z[i];
                acc[1] += r[i] * r[i];
            }
        });
        ++result.iterations;
        rnorm = std::sqrt(sums[1]);
        const double beta = sums[0] / rz;
        rz = sums[0];
        parallel_for(n, [&](int i) { d[i] = z[i] + beta * d[i]; });
    }
    result.relative_residual = rnorm / bnorm;
    return result;
}

}  // namespace xcut
