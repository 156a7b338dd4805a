#pragma once
// The first guess of a step's linear solve, from the solutions of the steps before it: the
// Galerkin projection of A x = b onto the span of the last m solutions, formed with this step's A.
//
// Method: Fischer, "Projection techniques for iterative solution of Ax = b with successive
// right-hand sides", Comput. Methods Appl. Mech. Engrg. 163 (1998): the best guess in the A-norm
// from a space of earlier solutions. Fischer keeps that space A-orthonormal for a fixed A. Here A
// changes every step (rotations, contacts), and a basis orthonormal for an older A drifts: in a
// measurement on the 53k-tet block its guesses grew worse than the previous step's solution alone
// after about ten steps. So the space is kept as the raw solutions, made Euclidean-orthonormal each
// step (modified Gram-Schmidt, two passes), and the small system Q^T A Q a = Q^T b is formed with the
// current A: m products a step, no stale quantity. The projection contains the previous step's
// solution (the guess before this stage), so in exact arithmetic its A-norm error is never larger
// than that guess's.
//
// Every sum runs on one thread in a fixed order: the same bits for any thread count.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "components/linear_system.h"

namespace xcut {

/// A direction whose remainder after orthogonalisation is below this share of its length is
/// dropped: it lies in the span of the others to round-off.
constexpr double kGuessDependence = 1e-10;

/// The kept solutions made orthonormal (modified Gram-Schmidt, twice), dependent ones dropped: the
/// columns of the result. Serial: a few vectors that stay in cache, and Eigen's fixed-order sums.
inline Eigen::MatrixXd orthonormal_basis(const std::vector<Eigen::VectorXd>& solutions) {
    const Eigen::Index n = solutions.empty() ? 0 : solutions.front().size();
    Eigen::MatrixXd q(n, static_cast<Eigen::Index>(solutions.size()));
    Eigen::Index m = 0;
    for (const Eigen::VectorXd& s : solutions) {
        Eigen::VectorXd v = s;
        const double length = v.norm();
        for (int pass = 0; pass < 2; ++pass)
            for (Eigen::Index j = 0; j < m; ++j) v -= q.col(j).dot(v) * q.col(j);
        const double rest = v.norm();
        if (!(length > 0.0) || !(rest > kGuessDependence * length)) continue;
        q.col(m++) = v / rest;
    }
    return q.leftCols(m);
}

/// x = Q (Q^T A Q)^-1 Q^T b, Q an orthonormal basis of the kept solutions' span (its columns);
/// `product(Q, AQ)` sets AQ = A Q with this step's A. False, x untouched, when nothing is kept or
/// the projected system is not positive definite (then the caller's own guess stands).
template <class Product>
bool projected_guess(const SolutionHistory& history, Product&& product, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    const Eigen::MatrixXd q = orthonormal_basis(history.solutions);
    const Eigen::Index m = q.cols();
    if (m == 0) return false;
    Eigen::MatrixXd aq(q.rows(), m), G(m, m);
    product(q, aq);
    Eigen::VectorXd c(m);
    for (Eigen::Index j = 0; j < m; ++j) {  // dots, not Eigen's matrix product, which may split its sums over threads
        c[j] = q.col(j).dot(b);
        for (Eigen::Index i = 0; i <= j; ++i) G(i, j) = G(j, i) = q.col(i).dot(aq.col(j));
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(G);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return false;
    const Eigen::VectorXd a = ldlt.solve(c);
    if (!a.allFinite()) return false;
    x.setZero(b.size());
    for (Eigen::Index j = 0; j < m; ++j) x += a[j] * q.col(j);
    return true;
}

/// Keeps `x` (held entries zeroed by `mask`) as the newest solution under `key`, the oldest
/// dropped past `capacity`; a new key starts the history again.
inline void remember_solution(SolutionHistory& history, const GuessKey& key, int capacity, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& mask) {
    if (!(history.key == key)) history.solutions.clear(), history.key = key;
    if (capacity <= 0) return history.solutions.clear();
    if (static_cast<int>(history.solutions.size()) >= capacity) history.solutions.erase(history.solutions.begin());
    history.solutions.push_back(x.cwiseProduct(mask));
}

}  // namespace xcut
