// The smoothed-aggregation multigrid preconditioner (systems/kernels/solver/amg.h) and the amg linear
// method: the V-cycle is a symmetric positive definite operator, the same bits on 1 and 2 threads;
// its Chebyshev bound lies above the spectrum; CG with it converges in a few tens of iterations where
// block Jacobi needs hundreds; the hierarchy is renewed at a cut and when the step's stiffness weight
// grows, and kept otherwise. At a cut: LinearSolver.PreconditionerFollowsACut; replays:
// LinearSolver.KeptPreconditionersAreDeterministic.
#include <gtest/gtest.h>

#include <random>

#include "engine/parallel.h"
#include "systems/kernels/solver/amg.h"
#include "systems/solver/linear_assembly.h"
#include "systems/solver/linear_solver.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::deformed;

constexpr double kMassScale = 1.0, kStiffScale = 1e-4;  // A = M + 1e-4 s^2 K: a 0.01 s step

/// A deformed 20 x 12 x 10 block (2,541 nodes) with its A assembled.
World block_with_matrix() {
    World w = deformed(false, Eigen::Vector3i(20, 12, 10));
    ensure_linear_pattern(w);
    assemble_step_matrix(w, xcut_step_terms(), kMassScale, kStiffScale);
    return w;
}

Eigen::VectorXd random_vector(int n, const Eigen::VectorXd& mask, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd v(n);
    for (int i = 0; i < n; ++i) v[i] = u(rng) * mask[i];
    return v;
}

Eigen::VectorXd cycle(AmgHierarchy& h, const LinearSystem& A, const Eigen::VectorXd& r, int threads) {
    Eigen::VectorXd z(r.size());
#pragma omp parallel num_threads(threads)
    amg_cycle_in_team(h, A, r, z);
    return z;
}

// The coarse operators' storage by runs of consecutive columns: runs of every length from 1 to 13
// (the kernel's four-wide sums, its overlapping last four, its scalar tail for runs under four),
// empty rows and a last column: the product equals the single-precision matrix's to round-off.
TEST(Amg, RunStorageMultipliesLikeTheMatrix) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int rows = 40, cols = 120;
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < rows; ++i) {
        if (i % 7 == 3) continue;  // an empty row
        int c = i % 5;
        for (int run = 1; run <= 13 && c < cols; run += 1 + i % 3) {
            for (int k = 0; k < run && c < cols; ++k, ++c) entries.emplace_back(i, c, u(rng));
            c += 1 + (i + run) % 4;  // a gap: the next run
        }
    }
    entries.emplace_back(0, cols - 1, 0.5);  // a run of one at the last column
    CsrMatrix M(rows, cols);
    M.setFromTriplets(entries.begin(), entries.end());
    const RunMatrix runs = to_runs(M);
    EXPECT_EQ(runs.rows(), rows);
    EXPECT_EQ(runs.cols(), cols);
    EXPECT_EQ(runs.nonZeros(), M.nonZeros());
    EXPECT_LT(runs.run_column.size(), static_cast<size_t>(M.nonZeros()) / 3) << "runs, not single entries";
    EXPECT_EQ(runs.row_start[3 + 1], runs.row_start[3]) << "row 3 is empty";
    const Eigen::VectorXd v = random_vector(cols, Eigen::VectorXd::Ones(cols), 3);
    Eigen::VectorXd y;
    run_product(runs, v, y);
    const Eigen::VectorXd expected = M.cast<float>().cast<double>() * v;
    ASSERT_EQ(y.size(), rows);
    for (int i = 0; i < rows; ++i) EXPECT_NEAR(y[i], expected[i], 1e-14 * (1.0 + std::abs(expected[i]))) << "row " << i;
}

// The setup's own sparse product against Eigen's: the same pattern and the same bits (random
// matrices with empty rows, explicit zeros and entries that cancel), for the operand shapes of a
// Galerkin product (A P and R (A P)).
TEST(Amg, SparseProductIsEigensBitForBit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto random_matrix = [&](int rows, int cols, double density) {
        std::vector<Eigen::Triplet<double>> t;
        for (int i = 0; i < rows; ++i) {
            if (i % 7 == 3) continue;  // an empty row
            for (int j = 0; j < cols; ++j)
                if (std::abs(u(rng)) < density) t.emplace_back(i, j, j % 11 == 5 ? 0.0 : u(rng));
        }
        CsrMatrix M(rows, cols);
        M.setFromTriplets(t.begin(), t.end());
        return M;
    };
    for (int trial = 0; trial < 6; ++trial) {
        // The last trial large enough to be shared among two threads (1,024 rows a share at least).
        const int n = trial < 5 ? 90 : 3000;
        set_thread_count(trial < 5 ? 1 : 2);
        const CsrMatrix A = random_matrix(n, n, trial < 5 ? 0.08 : 0.004), P = random_matrix(n, n / 5, trial < 5 ? 0.2 : 0.01);
        const CsrMatrix AP = sparse_product(A, P), R = P.transpose();
        const CsrMatrix expected_AP = A * P, RAP = sparse_product(R, AP), expected_RAP = R * expected_AP;
        for (const auto& [got, want] : {std::pair{&AP, &expected_AP}, std::pair{&RAP, &expected_RAP}}) {
            ASSERT_EQ(got->nonZeros(), want->nonZeros());
            ASSERT_TRUE(std::equal(got->outerIndexPtr(), got->outerIndexPtr() + got->rows() + 1, want->outerIndexPtr()));
            ASSERT_TRUE(std::equal(got->innerIndexPtr(), got->innerIndexPtr() + got->nonZeros(), want->innerIndexPtr()));
            for (Eigen::Index k = 0; k < got->nonZeros(); ++k)
                ASSERT_EQ(got->valuePtr()[k], want->valuePtr()[k]) << "entry " << k << " of trial " << trial;
        }
    }
    set_thread_count(2);
}

TEST(Amg, CycleIsSymmetricPositiveDefiniteAndThreadIndependent) {
    World w = block_with_matrix();
    const Eigen::VectorXd mask = free_mask(w);
    AmgHierarchy h;
    build_amg(w.linear, w.nodes.position, mask, h);
    amg_update_finest(h, w.linear);
    ASSERT_TRUE(h.ok);
    ASSERT_GE(h.levels.size(), 2u) << "a coarse level at least";
    const int n = 3 * w.linear.rows();
    for (uint64_t seed = 1; seed <= 4; ++seed) {
        const Eigen::VectorXd r1 = random_vector(n, mask, seed), r2 = random_vector(n, mask, seed + 10);
        const Eigen::VectorXd z1 = cycle(h, w.linear, r1, 1).cwiseProduct(mask);
        const Eigen::VectorXd z2 = cycle(h, w.linear, r2, 1).cwiseProduct(mask);
        EXPECT_NEAR(r2.dot(z1), r1.dot(z2), 1e-9 * std::sqrt(r1.dot(z1) * r2.dot(z2)));
        EXPECT_GT(r1.dot(z1), 0.0);
        EXPECT_EQ(cycle(h, w.linear, r1, 2), cycle(h, w.linear, r1, 1)) << "1 and 2 threads: the same bits";
    }
}

// The Chebyshev smoother converges for eigenvalues of D^-1 A below 1.1 (1 + 1/15) lambda_max (its
// interval [upper / 15, upper], upper = 1.1 lambda_max): the estimate must be no more than 14 % low.
// Checked against 400 power iterations.
TEST(Amg, EigenvalueEstimateBoundsTheSpectrum) {
    World w = block_with_matrix();
    const Eigen::VectorXd mask = free_mask(w);
    AmgHierarchy h;
    build_amg(w.linear, w.nodes.position, mask, h);
    const int n = 3 * w.linear.rows();
    Eigen::VectorXd v = random_vector(n, Eigen::VectorXd::Ones(n), 5), y(n);
    double power = 0.0;
    for (int it = 0; it < 400; ++it) {
        linear_multiply(w.linear, v, y);
        y = y.cwiseProduct(h.levels[0].inverse_diagonal);
        power = y.norm() / v.norm();
        v = y / y.norm();
    }
    EXPECT_GE(1.1 * (1.0 + 1.0 / 15.0) * h.levels[0].lambda_max, power);
    EXPECT_LE(h.levels[0].lambda_max, 1.01 * power) << "not far above it either (the smoother would weaken)";
}

// The amg method against block Jacobi on the same system: both reach 1e-8, amg in under a fifth of
// the iterations (measured: 16 against 285).
TEST(Amg, ConvergesInAFractionOfBlockJacobisIterations) {
    World w = block_with_matrix();
    const Eigen::VectorXd mask = free_mask(w);
    const Eigen::VectorXd b = (w.forces.force + Eigen::VectorXd::Constant(mask.size(), 1e-3)).cwiseProduct(mask);
    w.solver.cg_tolerance = 1e-8;
    w.solver.cg_max_iterations = 2000;
    int iterations[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        w.linear.method = k == 0 ? "amg" : "block_jacobi";
        Eigen::VectorXd x = Eigen::VectorXd::Zero(mask.size());
        const LinearSolve s = solve_linear(w, xcut_step_terms(), kMassScale, kStiffScale, b, mask, x);
        EXPECT_TRUE(s.converged) << w.linear.method;
        iterations[k] = s.cg.iterations;
        Eigen::VectorXd ax;
        linear_multiply(w.linear, x, ax);
        EXPECT_LE((ax - b).cwiseProduct(mask).norm(), 1e-7 * b.norm()) << "true residual, " << w.linear.method;
    }
    EXPECT_LT(5 * iterations[0], iterations[1]) << "amg " << iterations[0] << ", block_jacobi " << iterations[1];
}

// Kept while the step's matrix only drifts; renewed when the stiffness weight grows (a longer step:
// the smoother's bound would no longer hold), never when it shrinks (a substep).
TEST(Amg, HierarchyIsRenewedWhenTheStiffnessWeightGrows) {
    World w = block_with_matrix();
    const Eigen::VectorXd mask = free_mask(w);
    const Eigen::VectorXd b = w.forces.force.cwiseProduct(mask);
    w.linear.method = "amg";
    const auto solve = [&](double stiff_scale) {
        Eigen::VectorXd x = Eigen::VectorXd::Zero(mask.size());
        EXPECT_TRUE(solve_linear(w, xcut_step_terms(), kMassScale, stiff_scale, b, mask, x).converged);
        return w.linear.factorizations;
    };
    EXPECT_EQ(solve(kStiffScale), 1);
    EXPECT_EQ(solve(kStiffScale), 1) << "kept";
    EXPECT_EQ(solve(kStiffScale / 4), 1) << "a substep keeps it";
    EXPECT_EQ(solve(kStiffScale * 4), 2) << "a longer step renews it";
}

}  // namespace
}  // namespace xcut
