// The cholesky method's factor renewed off the step (systems/solver/factor_background.h) and the
// augmented block through which the old factor solves a grown system
// (systems/solver/factor_augment.h): exact against a dense solve of the grown matrix, taken at a
// fixed step, the same bits for any thread count and load, every step at the scene's tolerance,
// and close to factoring in the step.
#include <Eigen/SparseCholesky>
#include <array>
#include <random>

#include "systems/kernels/solver/block_sparse.h"
#include "systems/solver/beside_augment.h"
#include "systems/solver/beside_factor.h"
#include "systems/solver/cholesky_factor.h"
#include "systems/solver/factor_augment.h"
#include "systems/solver/factor_background.h"
#include "systems/solver/linear_assembly.h"
#include "tests/systems/background_runs.h"

namespace xcut {
namespace {

/// A dense SPD matrix of 3 `nodes` rows (diagonally dominant, so it stays SPD with blocks zeroed),
/// the axes whose mask is 0 filtered as the assembly filters them (row and column zero, diagonal 1).
Eigen::MatrixXd dense_spd(int nodes, const Eigen::VectorXd& mask) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::MatrixXd G(3 * nodes, 3 * nodes);
    for (int i = 0; i < G.size(); ++i) G.data()[i] = u(rng);
    Eigen::MatrixXd M = G * G.transpose() + 30.0 * nodes * Eigen::MatrixXd::Identity(3 * nodes, 3 * nodes);
    for (int i = 0; i < 3 * nodes; ++i)
        if (mask[i] == 0.0) M.row(i).setZero(), M.col(i).setZero(), M(i, i) = 1.0;
    return M;
}

/// The first `nodes` block rows and columns of M as the assembled system stores them (every block).
LinearSystem block_system(const Eigen::MatrixXd& M, int nodes) {
    LinearSystem A;
    A.row_offset.push_back(0);
    for (int i = 0; i < nodes; ++i) {
        for (int j = 0; j < nodes; ++j) {
            A.column.push_back(j);
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) A.value.push_back(M(3 * i + r, 3 * j + c));
        }
        A.diagonal.push_back(static_cast<int>(A.column.size()) - nodes + i);
        A.row_offset.push_back(static_cast<int>(A.column.size()));
    }
    A.topology = 40 + nodes;
    return A;
}

/// A factor of the grown matrix's old block in the jump basis (AMD ordering).
struct JumpFactor {
    Eigen::SparseMatrix<double> L;
    std::vector<int> perm, parent;  ///< parent: per new scalar DOF, as FactorAugment::parent
    LowerFactor lf;
};

void make_jump_factor(const Eigen::MatrixXd& M, int old_nodes, const std::vector<int>& parent_node,
                      const Eigen::VectorXd& mask, JumpFactor& out) {
    const int base = 3 * old_nodes, n = static_cast<int>(M.rows());
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(n, n);  // (u, a) -> (x_old, x_new)
    for (size_t j = 0; j < parent_node.size(); ++j)
        for (int c = 0; c < 3; ++c) {
            const int q = 3 * static_cast<int>(j) + c, p = 3 * parent_node[j] + c;
            const bool free = mask[p] != 0.0 && mask[base + q] != 0.0;
            out.parent.push_back(free ? p : -1);
            if (free) T(base + q, p) = 1.0;
        }
    const Eigen::MatrixXd jump = T.transpose() * M * T;
    const Eigen::SparseMatrix<double> A11 = jump.topLeftCorner(base, base).sparseView();
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt(A11);
    ASSERT_EQ(llt.info(), Eigen::Success);
    out.L = llt.matrixL();
    out.L.makeCompressed();
    out.perm.resize(base);
    for (int k = 0; k < base; ++k) out.perm[k] = llt.permutationPinv().indices()[k];
    ASSERT_TRUE(view_columns(base, out.L.outerIndexPtr(), nullptr, out.L.innerIndexPtr(), out.L.valuePtr(), out.perm.data(), out.lf));
}

/// The augmented solve of A = M's first `nodes` blocks against a dense solve: equal when the factor
/// is of the old block in the jump basis (M is then T^T A' T itself).
void expect_exact(const Eigen::MatrixXd& M, const JumpFactor& jf, FactorAugment& g, const Eigen::VectorXd& mask) {
    const int n = static_cast<int>(M.rows());
    ASSERT_TRUE(extend_augment(block_system(M, n / 3), jf.lf, jf.parent, g));
    EXPECT_EQ(g.columns(), n - jf.lf.rows());
    const Eigen::VectorXd r = Eigen::VectorXd::Random(n).cwiseProduct(mask);
    Eigen::VectorXd z;
    apply_augmented(jf.lf, &g, nullptr, r, z);
    const Eigen::VectorXd expected = M.llt().solve(r);
    EXPECT_LE((z - expected).norm(), 1e-10 * expected.norm()) << "largest difference " << (z - expected).cwiseAbs().maxCoeff();
}

/// expect_exact on a fresh augmented block: `old_nodes` old nodes, a phantom per entry of `parent_node`.
void expect_exact_fresh(int old_nodes, const std::vector<int>& parent_node, const Eigen::VectorXd& mask) {
    const Eigen::MatrixXd M = dense_spd(old_nodes + static_cast<int>(parent_node.size()), mask);
    JumpFactor jf;
    make_jump_factor(M, old_nodes, parent_node, mask, jf);
    FactorAugment g;
    expect_exact(M, jf, g, mask);
}

TEST(FactorAugment, ExactWhenTheFactorIsTheOldBlockInTheJumpBasis) {
    expect_exact_fresh(8, {0, 5, 2}, Eigen::VectorXd::Ones(33));
}

TEST(FactorAugment, ExactWithHeldAxes) {
    Eigen::VectorXd mask = Eigen::VectorXd::Ones(33);
    mask[0] = mask[1] = 0.0;    // node 0 held in x and y: its phantom's jump there has no parent
    mask[3 * 8 + 6 + 2] = 0.0;  // the third phantom's z held
    expect_exact_fresh(8, {0, 5, 2}, mask);
}

TEST(FactorAugment, NoNewDofsIsTheFactorAlone) { expect_exact_fresh(6, {}, Eigen::VectorXd::Ones(18)); }

// Extended step by step (two phantoms, then a third): the kept columns are reused, and the result
// is the block built at once when the later phantom does not couple to the earlier ones. The later
// split appends in room made at the first (not in grown storage: fresh pages under the kept
// columns), and a successor factor's block takes that storage over (hand_on_columns).
TEST(FactorAugment, ExtendingKeepsTheColumnsAlreadySolved) {
    const Eigen::VectorXd mask = Eigen::VectorXd::Ones(33);
    Eigen::MatrixXd M = dense_spd(11, mask);
    M.block(30, 24, 3, 6).setZero(), M.block(24, 30, 6, 3).setZero();
    JumpFactor jf;
    make_jump_factor(M, 8, {0, 5, 2}, mask, jf);
    FactorAugment g;
    std::vector<int> first(jf.parent.begin(), jf.parent.begin() + 6);
    ASSERT_TRUE(extend_augment(block_system(M, 10), jf.lf, first, g));
    const std::vector<int> y_start = g.y_start;
    const std::vector<double> y_value = g.y_value;
    const double* storage = g.y_value.data();
    EXPECT_GE(g.y_row.capacity(), g.y_row.size() / 6 * 256) << "room for 256 columns at the first split's mean";
    expect_exact(M, jf, g, mask);
    EXPECT_TRUE(std::equal(y_value.begin(), y_value.end(), g.y_value.begin())) << "the first six columns were kept";
    EXPECT_EQ(g.y_start.size(), y_start.size() + 3);
    EXPECT_EQ(g.y_value.data(), storage) << "the third phantom's columns moved the first ones";
    const std::vector<double> made = g.y_value;
    FactorAugment successor;
    hand_on_columns(g, successor);
    EXPECT_FALSE(g.ok);
    EXPECT_TRUE(successor.y_start == std::vector<int>{0} && successor.y_value.empty());
    expect_exact(M, jf, successor, mask);
    EXPECT_EQ(successor.y_value.data(), storage) << "built in the storage handed on";
    EXPECT_EQ(successor.y_value, made);
}

// A term's block beside the kept factor (systems/solver/beside_augment.h): its preconditioner is the
// exact inverse of the whole system's Schur complement M - s C^T H'^-1 C (H' = H + 1e-8 diag H; held
// axes out of C), computed densely here, over a factor with phantoms (its augmented block) and
// without.
/// A block of k amplitudes coupled to every `stride`-th DOF from `first` (phantoms among them), C
/// dense beside it; H SPD.
BesideBlock random_block(int k, int n, int first, int stride, std::mt19937& rng, Eigen::MatrixXd& C, Eigen::MatrixXd& H) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    BesideBlock block;
    block.rows = k;
    C = Eigen::MatrixXd::Zero(k, n);
    Eigen::MatrixXd G(k, k);
    for (int i = 0; i < k; ++i)
        for (int d = first + i % 2; d < n; d += stride + i % 3) {
            C(i, d) = u(rng);
            block.coupling.emplace_back(i, d, C(i, d));
        }
    for (int i = 0; i < G.size(); ++i) G.data()[i] = u(rng);
    H = G * G.transpose() + 0.5 * Eigen::MatrixXd::Identity(k, k);
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) block.stiffness.emplace_back(i, j, H(i, j));
    return block;
}

/// Four blocks in turn over one factor, as a moving tip gives them: new DOFs, then the same DOFs
/// with new values (X_S kept), then a subset of them (X_S's columns kept, none solved), then rows
/// partly new (only those solved); each solve exact, X_S, G and F = Y_g^T X_S (its kept columns
/// with the rows they belong to, the new ones made) the bits of a build from nothing.
void expect_beside_exact(int old_nodes, const std::vector<int>& parent_node, const Eigen::VectorXd& mask) {
    const int nodes = old_nodes + static_cast<int>(parent_node.size()), n = 3 * nodes, k = 7;
    const Eigen::MatrixXd M = dense_spd(nodes, mask);
    JumpFactor jf;
    make_jump_factor(M, old_nodes, parent_node, mask, jf);
    FactorAugment g;
    const LinearSystem A = block_system(M, nodes);
    if (!parent_node.empty()) {
        ASSERT_TRUE(extend_augment(A, jf.lf, jf.parent, g));
    }
    std::mt19937 rng(11);
    const double s = 0.4;
    const FactorAugment* phantoms = parent_node.empty() ? nullptr : &g;
    BesideAugment b;
    int kept = 0;
    for (const auto& [first, stride] : {std::pair{0, 2}, std::pair{0, 2}, std::pair{1, 4}, std::pair{2, 3}}) {
        Eigen::MatrixXd C, H;
        const BesideBlock block = random_block(k, n, first, stride, rng, C, H);
        const int builds = b.s_builds, solved = b.s_solved;
        const std::vector<int> rows_before = b.s_rows;
        ASSERT_TRUE(build_beside_augment(A, jf.lf, 1, phantoms, block, s, mask, b));
        kept += b.s_builds == builds;
        // S changed over the same factor: only its new rows solved, and X_S and G the bits of a
        // build from nothing.
        int new_rows = 0;
        for (int row : b.s_rows) new_rows += !std::binary_search(rows_before.begin(), rows_before.end(), row);
        if (b.s_builds != builds) {
            EXPECT_EQ(b.s_solved - solved, new_rows);
        }
        if (first == 2) {
            EXPECT_GT(new_rows, 0) << "the last block's rows are partly new";
            EXPECT_LT(new_rows, static_cast<int>(b.s_rows.size())) << "and partly kept";
        }
        BesideAugment fresh;
        ASSERT_TRUE(build_beside_augment(A, jf.lf, 1, phantoms, block, s, mask, fresh));
        EXPECT_EQ(fresh.x_start, b.x_start);
        EXPECT_EQ(fresh.x_row, b.x_row);
        EXPECT_EQ(fresh.x_value, b.x_value) << "bit for bit";
        EXPECT_EQ(fresh.G, b.G) << "bit for bit";
        EXPECT_EQ(fresh.F, b.F) << "bit for bit";
        for (int d = 0; d < n; ++d)
            if (mask[d] == 0.0) C.col(d).setZero();
        H.diagonal() *= 1.0 + kBesideRegularization;
        const Eigen::MatrixXd K = M - s * C.transpose() * H.llt().solve(C);
        std::uniform_real_distribution<double> u(-1.0, 1.0);  // the test's own draws, not rand()'s
        Eigen::VectorXd r(n);
        for (int d = 0; d < n; ++d) r[d] = u(rng) * mask[d];
        Eigen::VectorXd z;
        apply_augmented(jf.lf, phantoms, &b, r, z);
        const Eigen::VectorXd expected = K.llt().solve(r);
        EXPECT_GT((expected - M.llt().solve(r)).norm(), 1e-4 * expected.norm()) << "the block changes the solve";
        EXPECT_LE((z - expected).norm(), 1e-10 * expected.norm()) << "largest difference " << (z - expected).cwiseAbs().maxCoeff();
    }
    EXPECT_EQ(kept, 1) << "the second block's DOFs were the first's: X_S kept once";
}

TEST(BesideAugment, ExactOverAFactorWithPhantomsAndHeldAxes) {
    Eigen::VectorXd mask = Eigen::VectorXd::Ones(33);
    mask[0] = mask[1] = 0.0;
    mask[3 * 8 + 6 + 2] = 0.0;
    expect_beside_exact(8, {0, 5, 2}, mask);
}

TEST(BesideAugment, ExactOverAFactorAlone) { expect_beside_exact(9, {}, Eigen::VectorXd::Ones(27)); }

/// A factor of nine nodes (serial 1, or 2 standing for its successor) and blocks of seven rows over
/// it, as a tip moving through cells gives them.
struct NineNodes {
    Eigen::VectorXd mask = Eigen::VectorXd::Ones(27);
    JumpFactor jf;
    LinearSystem A;
    std::mt19937 rng{5};
    Eigen::MatrixXd C, H;
    NineNodes() {
        const Eigen::MatrixXd M = dense_spd(9, mask);
        make_jump_factor(M, 9, {}, mask, jf);
        A = block_system(M, 9);
    }
    BesideBlock block(int first, int stride) { return random_block(7, 27, first, stride, rng, C, H); }
    bool build(const BesideBlock& block, uint64_t factor, BesideAugment& b) {
        return build_beside_augment(A, jf.lf, factor, nullptr, block, 0.4, mask, b);
    }
    /// b was last built for `block` over `factor`, its rows partly in `before`: only the others
    /// were solved since `solved`, and X_S and G are the bits of a build from nothing.
    void expect_kept_rows(const BesideBlock& block, uint64_t factor, const std::vector<int>& before, int solved,
                          const BesideAugment& b) {
        int new_rows = 0;
        for (int row : b.s_rows) new_rows += !std::binary_search(before.begin(), before.end(), row);
        ASSERT_GT(new_rows, 0);
        ASSERT_LT(new_rows, static_cast<int>(b.s_rows.size())) << "the two sets share rows";
        EXPECT_EQ(b.s_solved - solved, new_rows) << "only the new rows solved";
        BesideAugment fresh;
        ASSERT_TRUE(build(block, factor, fresh));
        EXPECT_EQ(fresh.s_solved, static_cast<int>(fresh.s_rows.size()));
        EXPECT_EQ(fresh.x_start, b.x_start);
        EXPECT_EQ(fresh.x_row, b.x_row);
        EXPECT_EQ(fresh.x_value, b.x_value) << "bit for bit";
        EXPECT_EQ(fresh.G, b.G) << "bit for bit";
        EXPECT_EQ(fresh.E, b.E);
    }
};

// A tip entering the next cell: S changes over the same factor, sharing some rows with the S
// before. Only the new rows are solved; X_S and G are the bits of a build from nothing.
TEST(BesideAugment, ANewSetOfRowsKeepsTheColumnsOfTheRowsItShares) {
    NineNodes t;
    BesideAugment b;
    ASSERT_TRUE(t.build(t.block(0, 3), 1, b));
    const std::vector<int> before = b.s_rows;
    const int solved = b.s_solved;
    const BesideBlock next = t.block(2, 2);
    ASSERT_TRUE(t.build(next, 1, b));
    EXPECT_EQ(b.s_builds, 2);
    t.expect_kept_rows(next, 1, before, solved, b);
}

// The columns made off the step for a successor factor (solve_beside_columns, for the block's rows
// two steps before the swap): the swap's build keeps those its S shares and solves only the rest;
// X_S and G the bits of a build from nothing.
TEST(BesideAugment, ColumnsMadeAheadAreKeptByTheNextBuild) {
    NineNodes t;
    BesideAugment b, ahead;
    ASSERT_TRUE(t.build(t.block(0, 3), 1, b));
    const std::vector<int> rows_ahead = b.s_rows;
    solve_beside_columns(t.jf.lf, 2, rows_ahead, ahead);  // the same factor as serial 2: a successor
    EXPECT_EQ(ahead.s_rows, rows_ahead);
    const int solved = b.s_solved;
    take_beside_columns(std::move(ahead), b);
    EXPECT_TRUE(b.unbuilt) << "its block is built at its next use";
    EXPECT_EQ(b.s_seeded, static_cast<int>(rows_ahead.size()));
    const BesideBlock next = t.block(2, 2);
    ASSERT_TRUE(t.build(next, 2, b));
    EXPECT_FALSE(b.unbuilt);
    t.expect_kept_rows(next, 2, rows_ahead, solved, b);
}

/// A grasp's block (GraspTerm::jump_block's form): one row per held point and axis, C = w^T (x)
/// e_axis over three nodes, H = -1/k; C returned dense.
BesideBlock grasp_block(int n, const std::vector<std::array<int, 3>>& points, double k, Eigen::MatrixXd& C) {
    BesideBlock block;
    C = Eigen::MatrixXd::Zero(3 * static_cast<int>(points.size()), n);
    for (const auto& nodes : points)
        for (int c = 0; c < 3; ++c, ++block.rows)
            for (int a = 0; a < 3; ++a) {
                const double w = 0.2 + 0.3 * a;  // barycentric weights 0.2, 0.5, 0.8 (normalized below)
                C(block.rows, 3 * nodes[a] + c) = w / 1.5;
                block.coupling.emplace_back(block.rows, 3 * nodes[a] + c, w / 1.5);
            }
    for (int i = 0; i < block.rows; ++i) block.stiffness.emplace_back(i, i, -1.0 / k);
    return block;
}

// Jaws that closed and others that opened since the factor was made: the factor of A + s K_then
// solves A + s K_now through the difference beside it (K_now's block with its H < 0, K_then's with
// H negated), exactly up to the regularization of H; over a factor with phantoms and held axes.
TEST(BesideAugment, AJumpOfHeldStiffnessIsSolvedExactly) {
    Eigen::VectorXd mask = Eigen::VectorXd::Ones(33);
    mask[0] = mask[1] = 0.0;
    const int n = 33;
    const double s = 0.4, k_then = 50.0, k_now = 80.0;
    Eigen::MatrixXd C_then, C_now;
    const BesideBlock then = grasp_block(n, {{0, 3, 4}, {4, 5, 6}}, k_then, C_then);
    const BesideBlock now = grasp_block(n, {{1, 2, 7}, {9, 2, 10}, {8, 6, 7}}, k_now, C_now);
    const Eigen::MatrixXd mask_m = mask * mask.transpose();
    const Eigen::MatrixXd A0 = dense_spd(11, mask);
    const Eigen::MatrixXd factored = A0 + (s * k_then * C_then.transpose() * C_then).cwiseProduct(mask_m);
    const Eigen::MatrixXd target = A0 + (s * k_now * C_now.transpose() * C_now).cwiseProduct(mask_m);
    JumpFactor jf;
    make_jump_factor(factored, 8, {0, 5, 2}, mask, jf);
    const LinearSystem A = block_system(target, 11);
    FactorAugment g;
    ASSERT_TRUE(extend_augment(block_system(factored, 11), jf.lf, jf.parent, g));
    BesideBlock jump;
    append_block(jump, now, 1.0), append_block(jump, then, -1.0);
    EXPECT_EQ(jump.rows, 15);
    EXPECT_TRUE(same_block(then, then));
    EXPECT_FALSE(same_block(jump, now));
    BesideAugment b;
    ASSERT_TRUE(build_beside_augment(A, jf.lf, 1, &g, jump, s, mask, b));
    EXPECT_TRUE(b.indefinite) << "a stiffness that adds: H < 0";
    const Eigen::VectorXd r = Eigen::VectorXd::Random(n).cwiseProduct(mask);
    Eigen::VectorXd z, without;
    apply_augmented(jf.lf, &g, &b, r, z);
    apply_augmented(jf.lf, &g, nullptr, r, without);
    const Eigen::VectorXd expected = target.llt().solve(r);
    EXPECT_GT((without - expected).norm(), 1e-2 * expected.norm()) << "the jump changes the solve";
    EXPECT_LE((z - expected).norm(), 1e-7 * expected.norm()) << "largest difference " << (z - expected).cwiseAbs().maxCoeff();
}

// The step's solve through views of CHOLMOD's supernodes (Eigen's dense kernels, no BLAS) is
// CHOLMOD's own solve, on a 3D grid Laplacian large enough for supernodes of many columns.
TEST(FactorBackground, SupernodeViewsSolveAsCholmodDoes) {
    const int g = 12, n = g * g * g;
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
        t.emplace_back(i, i, 6.1);
        for (int d : {1, g, g * g})
            if (i + d < n) t.emplace_back(i, i + d, -1.0), t.emplace_back(i + d, i, -1.0);
    }
    LinearFactor f(true);
    f.matrix.resize(n, n);
    f.matrix.setFromTriplets(t.begin(), t.end());
    ASSERT_TRUE(compute_factor(f, true));
    ASSERT_TRUE(f.lower);
    int widest = 0;
    for (const auto& s : f.lower->supernodes) widest = std::max(widest, s.cols);
    EXPECT_GT(widest, 8) << "supernodes of many columns";
    const Eigen::VectorXd r = Eigen::VectorXd::Random(n);
    Eigen::VectorXd z;
    f.solve(r, z);
    const Eigen::VectorXd expected = f.llt.solve(r);
    EXPECT_LE((z - expected).norm(), 1e-12 * expected.norm());
    EXPECT_LE((f.matrix * z - r).norm(), 1e-10 * r.norm());
    // Computed again in place, it is another factorization: what a block built on it is keyed by.
    const uint64_t first = f.serial;
    ASSERT_TRUE(compute_factor(f, false));
    EXPECT_NE(f.serial, first);
}

// A successor that is not SPD comes back with ok false (the step then factors in itself).
TEST(FactorBackground, AFailedFactorIsReported) {
    Eigen::MatrixXd M = 2.0 * Eigen::MatrixXd::Identity(6, 6);
    M(3, 3) = -1.0;
    auto pending = start_background_factor(block_system(M, 2), nullptr, {}, 0, 3, single_precision_from("auto"));
    double wait = -1.0;
    const std::shared_ptr<LinearFactor> f = take_when_due(*pending, wait);
    EXPECT_FALSE(f->ok);
    EXPECT_GE(wait, 0.0);
}

/// The default skin with cholesky through its incision (110 steps: the blade cuts from step 20;
/// with `overrides`, as `xcut run --set` takes them).
SkinRun run_skin(int threads, int factor_delay, int steps = 110, const std::vector<std::string>& overrides = {}) {
    return run_default_skin(threads, steps, [&](SolverSettings& s) {
        s.linear = "cholesky";
        s.factor_delay = factor_delay;
    }, overrides);
}

TEST(FactorBackground, NoStepFactorsThroughTheCut) {
    const SkinRun r = run_skin(2, 10);
    ASSERT_GT(r.cuts, 0) << "the blade cut during the run";
    EXPECT_GT(r.augmented, 0) << "steps solved the grown system through the augmented block";
    EXPECT_GT(r.swaps, 0) << "factors computed off the step were taken";
    int last_swap = -1, first_stale = -1;
    for (int i = 0; i < static_cast<int>(r.state.size()); ++i) {
        EXPECT_LE(r.residual[i], 1e-6) << "step " << i + 1;
        EXPECT_NE(r.state[i], 3) << "step " << i + 1 << " factored in the step";
        // The most: the load's factor while the slab first sags, before its successor arrives
        // (factored in the step, it was renewed at 9).
        EXPECT_LE(r.iterations[i], 15) << "step " << i + 1;
        if (r.state[i] == 1 && first_stale < 0) first_stale = i;
        if (r.state[i] != 2) continue;
        // A successor is taken ten steps after it was asked for: the first one ten steps after the
        // first stale step, the next ones at least ten steps apart.
        if (last_swap < 0) EXPECT_EQ(i, first_stale + 10) << "step " << i + 1;
        else EXPECT_GE(i - last_swap, 10) << "step " << i + 1;
        last_swap = i;
    }
}

TEST(FactorBackground, SameBitsForAnyThreadCountAndLoad) {
    expect_same_bits_for_any_thread_count_and_load([](int threads) { return run_skin(threads, 10); });
}

TEST(FactorBackground, CloseToFactoringInTheStep) {
    const SkinRun off = run_skin(2, 10), in = run_skin(2, 0);
    EXPECT_EQ(in.augmented, 0);
    EXPECT_EQ(in.swaps, 0) << "factor_delay 0: nothing is computed off the step";
    expect_close_to_renewing_in_the_step(off, in);
}

/// run_skin with the factor's solves in `precision` (solver.factor_precision).
SkinRun run_skin_in(const std::string& precision, int threads) {
    return run_skin(threads, 10, 110, {"solver.factor_precision=" + precision});
}

// The factor's solves in single precision (solver.factor_precision "single"; "auto" makes them so
// from 1 M non-zeros of L on, the default skin's 315 k keep double: the golden runs and
// LowerFactorSplit.AutoPrecisionIsSingleFromAMillionNonZeros): only the preconditioner changes, so
// every step still meets the CG tolerance and the positions stay within its effect of the double
// run's.
TEST(FactorBackground, SinglePrecisionSolvesMeetTheToleranceOfDoubleOnes) {
    const SkinRun single = run_skin_in("single", 2), twice = run_skin_in("double", 2);
    ASSERT_GT(single.cuts, 0) << "the blade cut during the run";
    EXPECT_EQ(single.cuts, twice.cuts);
    EXPECT_GT(single.swaps, 0) << "single-precision factors computed off the step were taken";
    double max_u = 0.0, max_diff = 0.0;
    int more = 0;
    for (size_t i = 0; i < single.residual.size(); ++i) {
        EXPECT_LE(single.residual[i], 1e-6) << "step " << i + 1;
        more += single.iterations[i] - twice.iterations[i];
    }
    for (size_t i = 0; i < twice.position.size(); ++i) {
        max_diff = std::max(max_diff, (single.position[i] - twice.position[i]).norm());
        max_u = std::max(max_u, std::abs(twice.position[i].z()));
    }
    std::printf("  single against double: positions differ by at most %.3g m (sag %.3g m); %d CG iterations more in all\n",
                max_diff, max_u, more);
    EXPECT_GT(max_diff, 0.0) << "the single-precision solves ran";
    EXPECT_LT(max_diff, 1e-6 * std::max(max_u, 1e-3)) << "largest difference " << max_diff << " m";
    EXPECT_LE(more, static_cast<int>(single.residual.size()) / 10) << "at most one CG iteration more in ten steps";
}

TEST(FactorBackground, SinglePrecisionSolvesHaveTheSameBitsForAnyThreadCountAndLoad) {
    expect_same_bits_for_any_thread_count_and_load([](int threads) { return run_skin_in("single", threads); });
}

// The default skin with the crack front at the blade: its block rides on each factor renewed off the
// step, and the columns of X_S it needs over a successor are made off the step with it, so the
// step that takes a factor solves only the rows the front reached since they were asked for
// (their bits are those solved in the step: GoldenRuns' skin_slab_front).
TEST(FactorBackground, AFrontsBlockTakesItsColumnsWithTheSuccessor) {
    set_thread_count(2);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json", {"cutter.tip={}"});
    scene.visual_subdivisions = scene.collision_subdivisions = -1;
    scene.solver.linear = "cholesky";
    auto sim = make_simulation(scene, false);
    const LinearSystem& A = sim->world.linear;
    int swaps_with_front = 0;
    for (int i = 0; i < 110; ++i) {
        const int swaps = A.swaps;
        const int seeded = A.beside_factor ? A.beside_factor->moving.s_seeded : 0;
        const int solved = A.beside_factor ? A.beside_factor->moving.s_solved : 0;
        step_simulation(*sim);
        EXPECT_LE(sim->world.metrics.current.cg_residual, 1e-6) << "step " << i + 1;
        if (A.swaps == swaps || !A.beside_factor) continue;
        const BesideAugment& b = A.beside_factor->moving;
        if (!b.ok || b.factor != A.factor->serial) continue;  // no front's block over the factor taken
        ++swaps_with_front;
        EXPECT_GT(b.s_seeded, seeded) << "step " << i + 1 << ": the swap took columns made off the step";
        EXPECT_LT(b.s_solved - solved, static_cast<int>(b.s_rows.size()) / 2)
            << "step " << i + 1 << ": most of the block's columns were made off the step";
    }
    EXPECT_GE(swaps_with_front, 3) << "factors were taken while the front moved";
}

/// The default skin with a crack front at the blade, cholesky (through the blade's stop at step 122
/// and some steps after it when `steps` reaches past it).
SkinRun run_skin_front(int threads, int steps, int factor_delay) { return run_skin(threads, factor_delay, steps, {"cutter.tip={}"}); }

TEST(FactorBackground, AFrontsRunHasTheSameBitsForAnyThreadCountAndLoad) {
    expect_same_bits_for_any_thread_count_and_load([](int threads) { return run_skin_front(threads, 80, 10); });
}

// The front's block beside the factor in use from its first step to well after the blade stopped
// (no step factors the whole system: systems/solver/beside_factor.h), against that system's factor
// made in the step: the same cut, positions within the tolerance's effect.
TEST(FactorBackground, AFrontBesideTheFactorInUseIsCloseToFactoringTheWholeSystem) {
    const SkinRun off = run_skin_front(2, 150, 10), in = run_skin_front(2, 150, 0);
    for (size_t i = 1; i < off.state.size(); ++i) {
        EXPECT_NE(off.state[i], 3) << "step " << i + 1 << " factored in the step";
        EXPECT_LE(off.residual[i], 1e-6) << "step " << i + 1;
    }
    EXPECT_GT(std::count(in.state.begin() + 1, in.state.end(), 3), 2) << "the front's first step and the stop factor M";
    expect_close_to_renewing_in_the_step(off, in);
}

// The step's copy of A for a preconditioner built off the step (copy_linear_system) is A, and after a
// split grows A by a few blocks it lands in the storage the last copy used: fresh pages cost the
// requesting step milliseconds (docs/BENCHMARKS.md, Real time through a cut).
TEST(FactorBackground, TheStepsCopyOfAGrownByACutReusesItsStorage) {
    LinearSystem A;
    const auto fill = [&](int rows) {
        A.row_offset.assign(1, 0), A.column.clear(), A.diagonal.clear();
        for (int i = 0; i < rows; ++i) {
            A.diagonal.push_back(static_cast<int>(A.column.size()));
            for (int j = std::max(0, i - 2); j <= std::min(rows - 1, i + 2); ++j) A.column.push_back(j);
            A.row_offset.push_back(static_cast<int>(A.column.size()));
        }
        A.value.resize(9 * A.column.size());
        for (size_t k = 0; k < A.value.size(); ++k) A.value[k] = 0.5 + static_cast<double>(k % 97) / 7.0;
        A.topology = 1000u + static_cast<uint64_t>(rows);
    };
    const auto same = [](const LinearSystem& a, const LinearSystem& b) {
        return a.row_offset == b.row_offset && a.column == b.column && a.diagonal == b.diagonal && a.value == b.value &&
               a.topology == b.topology;
    };
    LinearSystem copy;
    fill(1000);
    copy_linear_system(A, copy);
    EXPECT_TRUE(same(A, copy));
    const double* values = copy.value.data();
    const int* columns = copy.column.data();
    fill(1030);  // a split: 30 more DOF nodes
    copy_linear_system(A, copy);
    EXPECT_TRUE(same(A, copy));
    EXPECT_EQ(copy.value.data(), values) << "the values went to fresh storage";
    EXPECT_EQ(copy.column.data(), columns) << "the pattern went to fresh storage";
    fill(2000);  // past the room: grown, and still A
    copy_linear_system(A, copy);
    EXPECT_TRUE(same(A, copy));
}

// The factor made at load copies A into the storage its successors are copied into, so the first
// request (the default skin asks at its second step) copies into pages touched at load, and the
// successors taken keep handing that storage on.
TEST(FactorBackground, TheLoadsFactorHoldsTheCopyItsSuccessorsUse) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
    scene.visual_subdivisions = scene.collision_subdivisions = -1;
    auto sim = make_simulation(scene, false);
    const LinearSystem& A = sim->world.linear;
    ASSERT_EQ(A.method, "cholesky");
    ASSERT_TRUE(A.factor && A.factor->snapshot);
    const FactorSnapshot* storage = A.factor->snapshot.get();
    EXPECT_EQ(storage->block.value, A.value) << "the copy at load is A";
    int swaps = 0;
    for (int i = 0; i < 40; ++i) {
        step_simulation(*sim);
        const bool swapped = sim->world.metrics.current.preconditioner == 2;
        swaps += swapped;
        ASSERT_TRUE(A.factor && A.factor->snapshot);
        EXPECT_EQ(A.factor->snapshot.get(), storage) << "step " << i + 1;
        if (!swapped) continue;
        // The successor's scalar copy stays in the snapshot for the next one, not in the factor.
        EXPECT_EQ(A.factor->matrix.nonZeros(), 0) << "step " << i + 1;
        ASSERT_TRUE(A.factor->lower);
        EXPECT_EQ(storage->scalar.rows(), A.factor->lower->rows()) << "step " << i + 1;
    }
    EXPECT_GE(swaps, 1) << "a successor was taken";
}

}  // namespace
}  // namespace xcut
