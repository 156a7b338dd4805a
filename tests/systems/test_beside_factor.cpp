// The factor of the system a beside term completes (systems/solver/beside_factor.h) against its
// closed form: M's leading block of M^-1 is the inverse of the Schur complement A - s C^T H^-1 C,
// computed here densely from A, C and H.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <random>

#include "systems/kernels/solver/block_sparse.h"
#include "systems/solver/beside_factor.h"
#include "systems/solver/linear_solver.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

/// A small plate's assembled A (static: A = K, its z axes held) and a block of 6 amplitudes coupled
/// to the DOFs of four nodes, H = B B^T of rank `rank` (a semi-definite H when rank < 6: C then has
/// no part along H's null space, as the branch functions' dependencies have none).
struct Case {
    World w;
    BesideBlock block;
    Eigen::MatrixXd C, H;
};

Case make_case(int rank) {
    Case c{testing::world_from_mesh(generate_plate(testing::grid({0.02, 0.02, 0}, {4, 5, 1}))), {}, {}, {}};
    World& w = c.w;
    for (int i = 0; i < w.nodes.count(); ++i)
        if (w.nodes.rest[i].x() < 1e-12) w.nodes.fixed[i] |= 3;
    w.solver.linear = "cholesky";
    const StepOperator op = xcut_step_terms();
    op.relinearize(w);
    fill_step_matrix(w, op, 0.0, 1.0);
    const int n3 = 3 * w.nodes.count(), m = 6;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::MatrixXd B(m, rank);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < rank; ++j) B(i, j) = u(rng);
    const double k = w.linear.value[9 * w.linear.diagonal[w.nodes.count() - 1]];  // a diagonal entry of A
    c.H = 0.5 * k * B * B.transpose();
    // C = (H's range) x (a random map onto the DOFs of the last four nodes): H^+ C is then bounded.
    Eigen::MatrixXd W(rank, n3);
    W.setZero();
    for (int i = w.nodes.count() - 4; i < w.nodes.count(); ++i)
        for (int d = 0; d < 2; ++d)
            for (int j = 0; j < rank; ++j) W(j, 3 * i + d) = 0.3 * u(rng);
    c.C = k * B * W;
    // Scaled so that s C^T H^+ C reaches 0.9 of A's smallest eigenvalue (s = 1): M then is
    // positive definite, and its Schur complement far from A.
    Eigen::SparseMatrix<double> a;
    copy_to_scalar(w.linear, a, true);
    const Eigen::VectorXd mask = free_mask(w);
    const Eigen::MatrixXd Cm = c.C * mask.asDiagonal();
    const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(a)).eigenvalues()[0];
    const double largest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(
        Cm.transpose() * c.H.completeOrthogonalDecomposition().pseudoInverse() * Cm).eigenvalues().maxCoeff();
    c.C *= std::sqrt(0.9 * smallest / largest);
    c.block.rows = m;
    for (int i = 0; i < m; ++i) {
        for (int j = 0; j < n3; ++j)
            if (c.C(i, j) != 0.0) c.block.coupling.emplace_back(i, j, c.C(i, j));
        for (int j = 0; j < m; ++j) c.block.stiffness.emplace_back(i, j, c.H(i, j));
    }
    return c;
}

TEST(BesideFactor, SolvesTheSchurComplementOfTheWholeSystem) {
    for (int rank : {6, 4}) {
        Case c = make_case(rank);
        const double s = 1.0;
        const Eigen::VectorXd mask = free_mask(c.w);
        BesideFactor f;
        ASSERT_TRUE(factor_beside(c.w.linear, c.block, s, mask, f)) << rank;
        Eigen::SparseMatrix<double> a;
        copy_to_scalar(c.w.linear, a, true);
        const Eigen::MatrixXd Cm = c.C * mask.asDiagonal();
        // Schur complement with H's pseudo-inverse (its null space carries nothing of C).
        const Eigen::MatrixXd S = Eigen::MatrixXd(a) - s * Cm.transpose() * c.H.completeOrthogonalDecomposition().pseudoInverse() * Cm;
        std::mt19937_64 rng(3);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        Eigen::VectorXd r(a.rows());
        for (Eigen::Index i = 0; i < r.size(); ++i) r[i] = u(rng) * mask[i];
        Eigen::VectorXd z;
        f.solve(r, z);
        const Eigen::VectorXd exact = S.ldlt().solve(r);
        EXPECT_LT((z - exact).norm(), 1e-6 * exact.norm()) << rank;
        // And the block matters: A's own inverse is far from it.
        const double apart = (Eigen::MatrixXd(a).ldlt().solve(r) - exact).norm() / exact.norm();
        EXPECT_GT(apart, 1e-2) << rank;
        std::printf("rank %d: |z - exact| %.2g, A^-1 r %.2g apart (relative)\n", rank, (z - exact).norm() / exact.norm(), apart);
    }
}

}  // namespace
}  // namespace xcut
