// Pure-kernel checks of the corotational element (paper App. B) and the rotation extraction.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "systems/kernels/corotational_kernel.h"
#include "systems/kernels/polar_decomposition.h"

namespace xcut {
namespace {

Mat3 random_rotation(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
    return q.normalized().toRotationMatrix();
}

TEST(PolarDecomposition, RecoversRotationOfStretchedRotation) {
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 50; ++trial) {
        const Mat3 R = random_rotation(rng);
        Mat3 S = Mat3::Identity();
        S(0, 0) = 1.3, S(1, 1) = 0.8, S(0, 1) = S(1, 0) = 0.1;
        const Mat3 got = extract_rotation(R * S, Mat3::Identity());
        EXPECT_LT((got - R).norm(), 1e-12) << "trial " << trial;
    }
}

// Four at a time (the force pass's batches): each lane agrees with the one-at-a-time iteration to
// round-off, lanes converging after different counts, an inverted lane taking the robust path.
TEST(PolarDecomposition, FourAtATimeAgreesWithOneAtATime) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        std::array<Mat3, 4> F, warm, R;
        for (int k = 0; k < 4; ++k) {  // F = Q P diag(s) P^T, stretches growing by lane
            const Mat3 P = random_rotation(rng);
            const double spread = 0.3 * (k + 1);
            const Vec3 s(std::exp(spread * u(rng)), std::exp(spread * u(rng)), std::exp(spread * u(rng)));
            F[k] = random_rotation(rng) * P * s.asDiagonal() * P.transpose();
            warm[k] = Mat3::Identity();
        }
        if (trial % 5 == 0) F[trial % 4].col(2) *= -1.0;  // an inverted lane: det F < 0
        extract_rotations4(F, warm, R);
        for (int k = 0; k < 4; ++k) {
            const Mat3 one = extract_rotation(F[k], warm[k]);
            EXPECT_LT((R[k] - one).norm(), 1e-13) << "trial " << trial << " lane " << k;
            EXPECT_NEAR(R[k].determinant(), 1.0, 1e-12);
        }
    }
}

TEST(PolarDecomposition, TwoDimensionalIsExact) {
    const double t = 0.7;
    Eigen::Matrix2d R;
    R << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
    Eigen::Matrix2d S;
    S << 1.2, 0.05, 0.05, 0.9;
    EXPECT_LT((extract_rotation(Eigen::Matrix2d(R * S)) - R).norm(), 1e-14);
}

// The matrix-free stiffness action equals the derivative of the force (rotation frozen): compare
// with central differences of corotational_forces.
TEST(CorotationalKernel, StiffnessProductIsForceDerivative) {
    std::array<Vec3, 4> X = {Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 1, 0), Vec3(0.1, 0.3, 1.1)};
    Mat3 Dm;
    for (int c = 0; c < 3; ++c) Dm.col(c) = X[c + 1] - X[0];
    const Mat3 dm_inv = Dm.inverse();
    const double V = Dm.determinant() / 6.0;
    const LameParameters lame{5.0, 3.0};
    std::mt19937_64 rng(3);
    const Mat3 R = random_rotation(rng);
    std::array<Vec3, 4> x, p;
    std::normal_distribution<double> n;
    for (int a = 0; a < 4; ++a) {
        x[a] = R * X[a] + 0.05 * Vec3(n(rng), n(rng), n(rng));
        p[a] = Vec3(n(rng), n(rng), n(rng));
    }
    std::array<Vec3, 4> kp;
    corotational_stiffness_product<3>(p, dm_inv, R, V, lame, kp);
    const double h = 1e-6;
    std::array<Vec3, 4> xp = x, xm = x, fp, fm;
    for (int a = 0; a < 4; ++a) xp[a] += h * p[a], xm[a] -= h * p[a];
    corotational_forces<3>(xp, dm_inv, R, V, lame, fp);
    corotational_forces<3>(xm, dm_inv, R, V, lame, fm);
    for (int a = 0; a < 4; ++a) EXPECT_LT((-(fp[a] - fm[a]) / (2 * h) - kp[a]).norm(), 1e-7);

    // The diagonal kernel agrees with the product on unit vectors.
    std::array<Vec3, 4> diag;
    corotational_stiffness_diagonal<3>(dm_inv, R, V, lame, diag);
    for (int a = 0; a < 4; ++a)
        for (int k = 0; k < 3; ++k) {
            std::array<Vec3, 4> e{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, out;
            e[a][k] = 1.0;
            corotational_stiffness_product<3>(e, dm_inv, R, V, lame, out);
            EXPECT_NEAR(out[a][k], diag[a][k], 1e-12 * std::abs(diag[a][k]));
        }
}

// Energy is the potential of the force: f = -dW/dx along a random direction (R frozen at the polar
// rotation makes eps symmetric-stationary; check with central differences at fixed R).
TEST(CorotationalKernel, ForceIsMinusEnergyGradient2D) {
    std::array<Vec3, 4> X = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.9, 0), Vec3::Zero()};
    Eigen::Matrix2d Dm;
    Dm << 1, 0.3, 0, 0.9;
    const Eigen::Matrix2d dm_inv = Dm.inverse();
    const LameParameters lame{2.0, 1.0};
    std::array<Vec3, 4> x = {Vec3(0, 0, 0), Vec3(1.1, 0.05, 0), Vec3(0.25, 0.95, 0), Vec3::Zero()};
    const Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
    std::array<Vec3, 4> f, tmp;
    corotational_forces<2>(x, dm_inv, R, 0.45, lame, f);
    const double h = 1e-6;
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 2; ++k) {
            auto xp = x, xm = x;
            xp[a][k] += h, xm[a][k] -= h;
            const double dW = (corotational_forces<2>(xp, dm_inv, R, 0.45, lame, tmp) -
                               corotational_forces<2>(xm, dm_inv, R, 0.45, lame, tmp)) / (2 * h);
            EXPECT_NEAR(-dW, f[a][k], 1e-8);
        }
    (void)X;
}

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

TEST(PolarDecomposition, InvertedElementGivesProperRotation) {
    Mat3 F = Mat3::Identity();
    F(2, 2) = -0.5;  // flattened through itself
    const Mat3 R = extract_rotation(F, Mat3::Identity());
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_LT((R * R.transpose() - Mat3::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace xcut
