// The step's solves through a Cholesky factor's supernodes split over a team's threads by subtrees
// of the elimination tree (systems/solver/lower_factor.h): the same bits as the serial solve on 1,
// 2 and 3 threads and for 2 or 3 bins, and the solve CHOLMOD makes; the augmented solve of a grown
// system the same (systems/solver/beside_augment.h); all of it with the factor in single precision too.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <omp.h>
#include <string>
#include <vector>

#include "systems/solver/beside_augment.h"
#include "systems/solver/cholesky_factor.h"
#include "systems/solver/factor_augment.h"

namespace xcut {
namespace {

/// A grid of g x g x layers nodes, 3 DOFs each, and `extra_nodes` apart: a diagonally dominant
/// block Laplacian (neighbours -I, the diagonal 6.5 I plus a small SPD coupling of a node's axes).
Eigen::MatrixXd grid_matrix(int g, int layers, int extra_nodes) {
    const int grid = g * g * layers, nodes = grid + extra_nodes, n = 3 * nodes;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
    Eigen::Matrix3d coupling;
    coupling << 0.3, 0.1, 0.0, 0.1, 0.2, 0.05, 0.0, 0.05, 0.4;
    for (int i = 0; i < nodes; ++i) M.block<3, 3>(3 * i, 3 * i) = 6.5 * Eigen::Matrix3d::Identity() + coupling;
    for (int i = 0; i < grid; ++i)
        for (int d : {1, g, g * g})
            if (i + d < grid && (d != 1 || (i + 1) % g != 0) && (d != g || (i / g + 1) % g != 0)) {
                M.block<3, 3>(3 * i, 3 * (i + d)) = -Eigen::Matrix3d::Identity();
                M.block<3, 3>(3 * (i + d), 3 * i) = -Eigen::Matrix3d::Identity();
            }
    return M;
}

/// A viewed CHOLMOD factor of M, its solves split into `bins` bins (in single precision if `single`).
void factor_split(const Eigen::MatrixXd& M, int bins, LinearFactor& f, bool single = false) {
    f.matrix = M.sparseView();
    if (single) f.single_from = 0.0;
    ASSERT_TRUE(compute_factor(f, true));
    ASSERT_TRUE(f.lower);
    split_solves(*f.lower, bins, 0.0);
    ASSERT_EQ(f.lower->split.bins, bins);
    ASSERT_GE(f.lower->split.range.size(), static_cast<size_t>(bins));
    ASSERT_EQ(f.lower->is_single(), single);
}

/// How far a solve through the factor may be from an exact one, relative to its norm: round-off
/// in double; in single, about 1e-7 times the condition of L (a few units for these grids).
double solve_tolerance(bool single) { return single ? 1e-5 : 1e-12; }

/// The split solve by a team of `threads`.
Eigen::VectorXd team_solve(const LowerFactor& lf, const Eigen::VectorXd& r, int threads) {
    Eigen::VectorXd z(r.size());
    LowerFactor::Scratch sh;
    lf.prepare(sh);
#pragma omp parallel num_threads(threads)
    lf.solve_in_team(r, z, sh, LowerFactor::NoBetween{});
    return z;
}

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return a.size() == b.size() && std::equal(a.data(), a.data() + a.size(), b.data());
}

void expect_team_solves_have_the_serial_solves_bits(bool single) {
    const Eigen::MatrixXd M = grid_matrix(24, 2, 0);  // a thin layer, as the skin
    LinearFactor f(true);
    factor_split(M, 2, f, single);
    // Both bins hold a share of the work, the top separators the rest.
    std::vector<double> work(3, 0.0);
    for (size_t s = 0; s < f.lower->supernodes.size(); ++s) {
        const int k = f.lower->split.range_of[s];
        const double w = double(f.lower->supernodes[s].rows) * f.lower->supernodes[s].cols;
        work[k < 0 ? 2 : f.lower->split.bin_of[k]] += w;
    }
    EXPECT_GT(std::min(work[0], work[1]), 0.8 * std::max(work[0], work[1])) << "bins within 20 %";
    EXPECT_LT(work[2], work[0] + work[1]) << "most of the work below the top";

    const Eigen::VectorXd r = Eigen::VectorXd::Random(M.rows());
    Eigen::VectorXd serial;
    f.lower->solve(r, serial);
    const double error = (serial - f.llt.solve(r)).norm() / serial.norm();
    EXPECT_LE(error, solve_tolerance(single)) << "CHOLMOD's solve";
    if (single) {
        EXPECT_GT(error, 1e-12) << "the single-precision solve is not the double one";
    }
    for (int threads : {1, 2, 3}) EXPECT_TRUE(same_bits(team_solve(*f.lower, r, threads), serial)) << threads << " threads";
    LinearFactor three(true);
    factor_split(M, 3, three, single);
    EXPECT_TRUE(same_bits(team_solve(*three.lower, r, 3), serial)) << "three bins";
    EXPECT_TRUE(same_bits(team_solve(*three.lower, r, 2), serial)) << "three bins, two threads";
    LinearFactor whole(true);
    factor_split(M, 0, whole, single);  // not split: one thread of the team solves
    for (int threads : {1, 2}) EXPECT_TRUE(same_bits(team_solve(*whole.lower, r, threads), serial)) << "unsplit, " << threads;
}

TEST(LowerFactorSplit, TeamSolvesHaveTheSerialSolvesBits) { expect_team_solves_have_the_serial_solves_bits(false); }

// The same with the factor's entries and the solves in single precision (make_single): the bits
// of its own serial solve on any team, within single precision's reach of CHOLMOD's solve.
TEST(LowerFactorSplit, SinglePrecisionTeamSolvesHaveTheSerialSolvesBits) {
    expect_team_solves_have_the_serial_solves_bits(true);
}

/// A thin layer of g x g x 2 nodes, 3 DOFs each, as grid_matrix builds it but sparse (a dense one
/// of this size would not fit): the diagonal 6.5 I plus a small SPD coupling, neighbours -I.
Eigen::SparseMatrix<double> sparse_layer(int g) {
    const int grid = 2 * g * g;
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < grid; ++i) {
        for (int c = 0; c < 3; ++c) t.emplace_back(3 * i + c, 3 * i + c, 6.5 + 0.1 * c);
        for (int d : {1, g, g * g})
            if (i + d < grid && (d != 1 || (i + 1) % g != 0) && (d != g || (i / g + 1) % g != 0))
                for (int c = 0; c < 3; ++c) t.emplace_back(3 * i + c, 3 * (i + d) + c, -1.0), t.emplace_back(3 * (i + d) + c, 3 * i + c, -1.0);
    }
    Eigen::SparseMatrix<double> M(3 * grid, 3 * grid);
    M.setFromTriplets(t.begin(), t.end());
    return M;
}

/// Whether compute_factor made f's solves single precision for `precision` (solver.factor_precision).
bool made_single(const Eigen::SparseMatrix<double>& M, const std::string& precision, double& nonzeros) {
    LinearFactor f(true);
    f.matrix = M;
    f.single_from = single_precision_from(precision);
    EXPECT_TRUE(compute_factor(f, true));
    nonzeros = f.lnz;
    return f.lower && f.lower->is_single();
}

// solver.factor_precision: "auto" solves in single precision from 1 M non-zeros of L on (a
// factor that large is read from memory at every solve), in double below; "double" and "single"
// whatever the size.
TEST(LowerFactorSplit, AutoPrecisionIsSingleFromAMillionNonZeros) {
    double small = 0.0, large = 0.0, unused = 0.0;
    const Eigen::SparseMatrix<double> a = sparse_layer(24), b = sparse_layer(90);
    EXPECT_FALSE(made_single(a, "auto", small));
    EXPECT_TRUE(made_single(b, "auto", large));
    EXPECT_LT(small, 1e6);
    EXPECT_GE(large, 1e6);
    EXPECT_TRUE(made_single(a, "single", unused));
    EXPECT_FALSE(made_single(b, "double", unused));
}

// A grown system (phantom copies of four nodes, A = M in the copies' own DOFs) solved through the
// old block's factor in the jump basis and the augmented block: the team's bits are the serial
// solve's, and both are the dense solve of M.
void expect_augmented_team_solve_has_the_serial_solves_bits(bool single) {
    const int g = 8, old_nodes = g * g * g;
    const std::vector<int> parent_node = {37, 38, 100, 301};
    Eigen::MatrixXd M = grid_matrix(g, g, static_cast<int>(parent_node.size()));
    for (size_t j = 0; j < parent_node.size(); ++j) {  // each copy joined to its node's neighbour
        const int a = 3 * (old_nodes + static_cast<int>(j)), b = 3 * (parent_node[j] + 1);
        M.block<3, 3>(a, b) = M.block<3, 3>(b, a) = -0.5 * Eigen::Matrix3d::Identity();
    }
    const int base = 3 * old_nodes, n = static_cast<int>(M.rows());
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(n, n);  // (u, a) -> (x_old, x_new)
    std::vector<int> parent;
    for (size_t j = 0; j < parent_node.size(); ++j)
        for (int c = 0; c < 3; ++c) {
            const int q = 3 * static_cast<int>(j) + c;
            parent.push_back(3 * parent_node[j] + c);
            T(base + q, 3 * parent_node[j] + c) = 1.0;
        }
    LinearFactor f(true);
    factor_split((T.transpose() * M * T).topLeftCorner(base, base), 2, f, single);
    LinearSystem A;  // M as the assembled system stores it: every block
    A.row_offset.push_back(0);
    for (int i = 0; i < n / 3; ++i) {
        for (int j = 0; j < n / 3; ++j) {
            A.column.push_back(j);
            for (int rr = 0; rr < 3; ++rr)
                for (int cc = 0; cc < 3; ++cc) A.value.push_back(M(3 * i + rr, 3 * j + cc));
        }
        A.diagonal.push_back(static_cast<int>(A.column.size()) - n / 3 + i);
        A.row_offset.push_back(static_cast<int>(A.column.size()));
    }
    A.topology = 77;
    FactorAugment aug;
    ASSERT_TRUE(extend_augment(A, *f.lower, parent, aug));
    const Eigen::VectorXd r = Eigen::VectorXd::Random(n);
    Eigen::VectorXd serial;
    apply_augmented(*f.lower, &aug, nullptr, r, serial);
    EXPECT_LE((serial - M.llt().solve(r)).norm(), std::max(1e-10, solve_tolerance(single)) * serial.norm()) << "the dense solve";
    for (int threads : {1, 2}) {
        Eigen::VectorXd z(n);
        AugmentScratch sh;
        f.lower->prepare(sh.lower);
#pragma omp parallel num_threads(threads)
        apply_augmented_in_team(*f.lower, &aug, nullptr, r, z, sh);
        EXPECT_TRUE(same_bits(z, serial)) << threads << " threads";
    }
}

TEST(LowerFactorSplit, AugmentedTeamSolveHasTheSerialSolvesBits) { expect_augmented_team_solve_has_the_serial_solves_bits(false); }

// The same over a single-precision factor: the augmented block's columns are solved with the
// rounded entries too, so the block elimination stays consistent with the solves it corrects.
TEST(LowerFactorSplit, SinglePrecisionAugmentedTeamSolveHasTheSerialSolvesBits) {
    expect_augmented_team_solve_has_the_serial_solves_bits(true);
}

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

/// x = L^-1 P b for every column of b, column by column of L over the whole vector, from L's
/// views: the textbook sparse forward solve (Gilbert & Peierls 1988) the sparse solves must match.
Eigen::MatrixXd forward_by_columns(const LowerFactor& lf, const Eigen::MatrixXd& b) {
    const int n = lf.rows();
    Eigen::MatrixXd x(n, b.cols());
    for (int k = 0; k < n; ++k) x.row(k) = b.row(lf.perm[k]);
    for (const LowerFactor::Supernode& s : lf.supernodes)
        for (int k = 0; k < s.cols; ++k) {
            const size_t at = static_cast<size_t>(k) * s.rows;
            const auto L = [&](int p) { return s.value32 ? double(s.value32[at + p]) : s.value[at + p]; };
            const int j = s.first + k;
            x.row(j) /= L(k);
            for (int p = k + 1; p < s.rows; ++p) x.row(s.row[p]) -= L(p) * x.row(j);
        }
    return x;
}

// SparseForward (the augmented blocks' columns of L^-1 P B: systems/solver/factor_augment.h) visits
// the reach of a few entries only, a supernode's rows gathered at a time: every entry it takes has
// the bits of the whole column-by-column solve, and the entries it leaves are zero there; in double
// and in single precision.
void expect_sparse_forward_matches_the_whole_solve(bool single) {
    const Eigen::MatrixXd M = grid_matrix(7, 3, 0);
    LinearFactor f(true);
    factor_split(M, 2, f, single);
    const LowerFactor& lf = *f.lower;
    SparseForward<3> solver(lf);
    for (const std::vector<int>& rows : {std::vector<int>{5}, std::vector<int>{0, 77, 300}, std::vector<int>{200, 201, 440}}) {
        Eigen::MatrixXd b = Eigen::MatrixXd::Zero(lf.rows(), 3);
        for (size_t i = 0; i < rows.size(); ++i) {
            const double v[3] = {1.0 + i, -0.5 * i, 0.25};
            b.row(rows[i]) += Eigen::RowVector3d(v[0], v[1], v[2]);
            solver.add(rows[i], v);
        }
        solver.solve();
        const Eigen::MatrixXd x = forward_by_columns(lf, b);
        Eigen::MatrixXd taken = Eigen::MatrixXd::Zero(lf.rows(), 3);
        for (int j : solver.reach())
            for (int c = 0; c < 3; ++c) taken(j, c) = solver.x(j)[c];
        EXPECT_TRUE(std::equal(taken.data(), taken.data() + taken.size(), x.data())) << "the whole solve's bits";
        EXPECT_LT(static_cast<int>(solver.reach().size()), lf.rows()) << "a reach, not the whole factor";
        solver.clear();
    }
}

TEST(LowerFactorSplit, SparseForwardHasTheWholeSolvesBits) { expect_sparse_forward_matches_the_whole_solve(false); }

TEST(LowerFactorSplit, SinglePrecisionSparseForwardHasTheWholeSolvesBits) { expect_sparse_forward_matches_the_whole_solve(true); }

}  // namespace
}  // namespace xcut
