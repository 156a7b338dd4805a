// The dense kernels of the supernodal solves (systems/kernels/solver/supernode_solve.h): against
// Eigen's triangular solves and products in double precision (an independent reference), the
// entries above the diagonal never read, and the portable and AVX2 kernels to the bit.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "systems/kernels/solver/supernode_solve.h"

namespace xcut {
namespace {

/// Supernode shapes (rows, cols): single columns, blocks shorter and longer than the kernels' four
/// columns and eight lanes, no rows below, and tails of every length.
const int kShapes[][2] = {{1, 1}, {3, 3}, {5, 1}, {9, 2}, {12, 4}, {17, 4}, {30, 5}, {41, 7},
                          {64, 8}, {100, 13}, {203, 37}, {150, 150}};

/// A supernode's rows x cols block, column-major: a pivot in [1.5, 2.5] on each diagonal, entries
/// below of size up to 1/cols (a well-conditioned L11), NaN above the diagonal (never to be read).
std::vector<double> make_block(int rows, int cols, std::mt19937& g) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> L(static_cast<size_t>(rows) * cols);
    for (int j = 0; j < cols; ++j)
        for (int i = 0; i < rows; ++i)
            L[static_cast<size_t>(j) * rows + i] = i < j    ? std::numeric_limits<double>::quiet_NaN()
                                                   : i == j ? 2.0 + 0.5 * u(g)
                                                            : u(g) / cols;
    return L;
}

std::vector<double> make_vector(int n, std::mt19937& g) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<double> v(n);
    for (double& x : v) x = u(g);
    return v;
}

/// The forward kernel's result [x_s; -L21 x_s] and the backward's x_s = L11^-T (b_s - L21^T y), in
/// double by Eigen.
void reference(const std::vector<double>& Lv, int rows, int cols, const std::vector<double>& b, const std::vector<double>& y,
               Eigen::VectorXd& forward, Eigen::VectorXd& backward) {
    Eigen::MatrixXd L = Eigen::Map<const Eigen::MatrixXd>(Lv.data(), rows, cols);
    const Eigen::MatrixXd L11 = L.topRows(cols).triangularView<Eigen::Lower>();
    const Eigen::MatrixXd L21 = L.bottomRows(rows - cols);
    const Eigen::VectorXd bs = Eigen::Map<const Eigen::VectorXd>(b.data(), cols);
    const Eigen::VectorXd below = Eigen::Map<const Eigen::VectorXd>(y.data() + cols, rows - cols);
    forward.resize(rows);
    forward.head(cols) = L11.triangularView<Eigen::Lower>().solve(bs);
    forward.tail(rows - cols) = -(L21 * forward.head(cols));
    backward = L11.transpose().triangularView<Eigen::Upper>().solve(bs - L21.transpose() * below);
}

/// Both kernels of `k` on the block (rounded to Real) for b and the rows below y; returns [forward
/// result, backward result on the columns].
template <class Real>
std::vector<Real> apply(const SupernodeKernels<Real>& k, const std::vector<double>& Lv, int rows, int cols,
                        const std::vector<double>& b, const std::vector<double>& y) {
    const std::vector<Real> L(Lv.begin(), Lv.end());
    std::vector<Real> w(rows, Real(0));
    for (int i = 0; i < cols; ++i) w[i] = static_cast<Real>(b[i]);
    k.forward(L.data(), rows, cols, w.data());
    std::vector<Real> out = w;
    for (int i = 0; i < rows; ++i) w[i] = static_cast<Real>(i < cols ? b[i] : y[i]);
    k.backward(L.data(), rows, cols, w.data());
    out.insert(out.end(), w.begin(), w.begin() + cols);
    return out;
}

template <class Real>
void expect_near_reference(const SupernodeKernels<Real>& k, double tolerance) {
    std::mt19937 g(7);
    for (const auto& [rows, cols] : kShapes) {
        const std::vector<double> L = make_block(rows, cols, g), b = make_vector(rows, g), y = make_vector(rows, g);
        Eigen::VectorXd forward, backward;
        reference(L, rows, cols, b, y, forward, backward);
        const std::vector<Real> got = apply(k, L, rows, cols, b, y);
        double scale = std::max(forward.cwiseAbs().maxCoeff(), backward.cwiseAbs().maxCoeff()), worst = 0.0;
        for (int i = 0; i < rows; ++i) worst = std::max(worst, std::abs(got[i] - forward[i]));
        for (int i = 0; i < cols; ++i) worst = std::max(worst, std::abs(got[rows + i] - backward[i]));
        EXPECT_LE(worst, tolerance * scale) << k.name << " " << rows << " x " << cols;  // NaN fails too
    }
}

TEST(SupernodeSolve, PortableKernelsSolveAsEigenDoes) {
    expect_near_reference(supernode_kernels_generic<double>(), 1e-14);
    expect_near_reference(supernode_kernels_generic<float>(), 2e-6);
}

TEST(SupernodeSolve, Avx2KernelsHaveThePortableKernelsBits) {
    const SupernodeKernels<double>* wide = supernode_kernels_avx2<double>();
    const SupernodeKernels<float>* wide32 = supernode_kernels_avx2<float>();
    if (!wide || !wide32) GTEST_SKIP() << "this CPU has no AVX2";
    expect_near_reference(*wide, 1e-14);
    expect_near_reference(*wide32, 2e-6);
    std::mt19937 g(11);
    for (int round = 0; round < 4; ++round)
        for (const auto& [rows, cols] : kShapes) {
            const std::vector<double> L = make_block(rows, cols, g), b = make_vector(rows, g), y = make_vector(rows, g);
            const std::vector<double> d0 = apply(supernode_kernels_generic<double>(), L, rows, cols, b, y),
                                      d1 = apply(*wide, L, rows, cols, b, y);
            const std::vector<float> f0 = apply(supernode_kernels_generic<float>(), L, rows, cols, b, y),
                                     f1 = apply(*wide32, L, rows, cols, b, y);
            EXPECT_EQ(std::memcmp(d0.data(), d1.data(), d0.size() * sizeof(double)), 0) << rows << " x " << cols;
            EXPECT_EQ(std::memcmp(f0.data(), f1.data(), f0.size() * sizeof(float)), 0) << rows << " x " << cols;
        }
}

TEST(SupernodeSolve, TheSettingChoosesTheKernelsAndABadOneIsAnError) {
    EXPECT_STREQ(supernode_kernels_for<double>("generic").name, "generic");
    const char* best = supernode_kernels_avx2<double>() ? "avx2" : "generic";
    EXPECT_STREQ(supernode_kernels_for<double>(nullptr).name, best);
    EXPECT_STREQ(supernode_kernels_for<float>("auto").name, best);
    if (supernode_kernels_avx2<float>()) EXPECT_STREQ(supernode_kernels_for<float>("avx2").name, "avx2");
    else EXPECT_THROW(supernode_kernels_for<float>("avx2"), std::invalid_argument);
    try {
        supernode_kernels_for<double>("avx512");
        ADD_FAILURE() << "no error for XCUT_KERNELS=avx512";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("XCUT_KERNELS=avx512"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace xcut
