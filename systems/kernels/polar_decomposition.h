#pragma once
// Rotation part of a deformation gradient F = R S (polar decomposition), paper §3.1 and App. B
// (Müller & Gross 2004 use the polar decomposition for corotational FEM).
//
// 3D, det F > 0 (every element that is not inverted): Higham's scaled Newton iteration
// X <- (g X + X^-T / g) / 2 (Higham, "Computing the polar decomposition - with applications",
// SIAM J. Sci. Stat. Comput. 7, 1986), quadratically convergent: five to seven iterations reach
// round-off from F itself, so the result does not depend on the previous step.
// 3D, det F <= 0 (inverted or flat): the quaternion iteration of Müller, Bender, Chentanez & Macklin,
// "A Robust Method to Extract the Rotational Part of Deformations" (MIG 2016), warm-started from the
// previous rotation; it always returns a proper rotation, where Newton would return a reflection.
// 2D: exact, R = rotation by atan2(F10 - F01, F00 + F11).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <array>
#include <cmath>

namespace xcut {

/// Müller et al.'s iteration; stops when the corrective rotation angle is below `angle_tol` [rad].
inline Eigen::Matrix3d extract_rotation_robust(const Eigen::Matrix3d& F, const Eigen::Matrix3d& warm_start,
                                               double angle_tol = 1e-14, int max_iterations = 200) {
    Eigen::Quaterniond q(warm_start);
    q.normalize();
    for (int it = 0; it < max_iterations; ++it) {
        const Eigen::Matrix3d R = q.toRotationMatrix();
        const Eigen::Vector3d num =
            R.col(0).cross(F.col(0)) + R.col(1).cross(F.col(1)) + R.col(2).cross(F.col(2));
        const double den = std::abs(R.col(0).dot(F.col(0)) + R.col(1).dot(F.col(1)) + R.col(2).dot(F.col(2)));
        const Eigen::Vector3d omega = num / (den + 1e-300);
        const double angle = omega.norm();
        if (!(angle > angle_tol)) break;  // also stops on NaN rather than spinning
        q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle)) * q;
        q.normalize();
    }
    return q.toRotationMatrix();
}

/// Polar rotation of F. Newton stops when an update changes X by less than 1e-15 (Frobenius,
/// relative), i.e. at round-off; it is capped at 30 iterations. `newton_iterations`, when given,
/// receives the count (0 when the robust iteration ran instead): the benchmark's flop count uses it.
inline Eigen::Matrix3d extract_rotation(const Eigen::Matrix3d& F, const Eigen::Matrix3d& warm_start,
                                        int* newton_iterations = nullptr) {
    if (newton_iterations) *newton_iterations = 0;
    const double det = F.determinant();
    if (!(det > 1e-12 * F.squaredNorm() * F.norm())) return extract_rotation_robust(F, warm_start);
    Eigen::Matrix3d X = F;
    for (int it = 0; it < 30; ++it) {
        if (newton_iterations) *newton_iterations = it + 1;
        const Eigen::Matrix3d Xinv_t = X.inverse().transpose();
        const double g = std::sqrt(Xinv_t.norm() / X.norm());  // Frobenius scaling
        const Eigen::Matrix3d next = 0.5 * (g * X + Xinv_t / g);
        const double change = (next - X).norm();
        X = next;
        if (change <= 1e-15 * 1.7320508075688772) break;  // |X|_F = sqrt(3) at convergence
    }
    return X;
}

/// The polar rotations of four deformation gradients at once (the force pass processes tetrahedra
/// in fours): the same scaled Newton iteration as extract_rotation, written on 4-wide arrays, one
/// lane per matrix, so the compiler vectorises it (two SSE2 or one AVX2 instruction an operation).
/// X^-T is the cofactor matrix over det X. A lane stops changing once its update is below the same
/// 1e-15 (Frobenius, relative); the loop ends when all four have, or after 30 iterations. A lane
/// with det F <= 1e-12 |F|^3 (inverted or flat) takes the robust iteration, warm-started from its
/// `warm_start`, as extract_rotation does. The result agrees with extract_rotation to round-off. A
/// lane's result depends on its own F alone (and, robust, its warm start): `robust`, when given,
/// says which lanes took the robust iteration.
inline void extract_rotations4(const std::array<Eigen::Matrix3d, 4>& F, const std::array<Eigen::Matrix3d, 4>& warm_start,
                               std::array<Eigen::Matrix3d, 4>& R, std::array<bool, 4>* robust_lanes = nullptr) {
    using A4 = Eigen::Array4d;
    std::array<A4, 9> X;  // X[3 r + c], lane k: entry (r, c) of matrix k
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 9; ++i) X[i][k] = F[k](i / 3, i % 3);
    const auto cofactors = [](const std::array<A4, 9>& m, std::array<A4, 9>& c) {
        c[0] = m[4] * m[8] - m[5] * m[7], c[1] = m[5] * m[6] - m[3] * m[8], c[2] = m[3] * m[7] - m[4] * m[6];
        c[3] = m[2] * m[7] - m[1] * m[8], c[4] = m[0] * m[8] - m[2] * m[6], c[5] = m[1] * m[6] - m[0] * m[7];
        c[6] = m[1] * m[5] - m[2] * m[4], c[7] = m[2] * m[3] - m[0] * m[5], c[8] = m[0] * m[4] - m[1] * m[3];
    };
    const auto squared_norm = [](const std::array<A4, 9>& m) {
        A4 n = A4::Zero();
        for (const A4& v : m) n += v * v;
        return n;
    };
    std::array<A4, 9> C;
    cofactors(X, C);
    const A4 det = X[0] * C[0] + X[1] * C[1] + X[2] * C[2];
    const A4 norm_f = squared_norm(X).sqrt();
    const Eigen::Array<bool, 4, 1> robust = !(det > 1e-12 * norm_f * norm_f * norm_f);  // NaN lanes too
    Eigen::Array<bool, 4, 1> done = robust;
    for (int it = 0; it < 30 && !done.all(); ++it) {
        if (it > 0) cofactors(X, C);
        const A4 d = X[0] * C[0] + X[1] * C[1] + X[2] * C[2];
        const A4 g = ((squared_norm(C).sqrt() / d.abs()) / squared_norm(X).sqrt()).sqrt();  // Frobenius scaling
        A4 change = A4::Zero();
        std::array<A4, 9> next;
        for (int i = 0; i < 9; ++i) {
            next[i] = 0.5 * (g * X[i] + C[i] / (d * g));  // X^-T = C / det
            change += (next[i] - X[i]).square();
        }
        for (int i = 0; i < 9; ++i) X[i] = done.select(X[i], next[i]);
        done = done || (change.sqrt() <= 1e-15 * 1.7320508075688772);
    }
    for (int k = 0; k < 4; ++k) {
        if (robust_lanes) (*robust_lanes)[k] = robust[k];
        if (robust[k]) {
            R[k] = extract_rotation_robust(F[k], warm_start[k]);
            continue;
        }
        for (int i = 0; i < 9; ++i) R[k](i / 3, i % 3) = X[i][k];
    }
}

inline Eigen::Matrix2d extract_rotation(const Eigen::Matrix2d& F) {
    const double theta = std::atan2(F(1, 0) - F(0, 1), F(0, 0) + F(1, 1));
    const double c = std::cos(theta), s = std::sin(theta);
    Eigen::Matrix2d R;
    R << c, -s, s, c;
    return R;
}

}  // namespace xcut
