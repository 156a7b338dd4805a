#pragma once
// Rotation part of a deformation gradient F = R S (polar decomposition), paper §3.1 and App. B
// (Müller & Gross 2004 use the polar decomposition for corotational FEM).
//
// 3D: the quaternion iteration of Müller, Bender, Chentanez & Macklin, "A Robust Method to Extract
// the Rotational Part of Deformations" (MIG 2016). Warm-started from the previous step's rotation it
// converges in one to three iterations; it stays well defined for degenerate and inverted elements,
// where an SVD-based polar decomposition needs sign fixes. For det F > 0 its fixed point is the
// polar rotation.
// 2D: exact, R = rotation by atan2(F10 - F01, F00 + F11).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace xcut {

/// Tolerance: iterate until the corrective rotation angle is below `angle_tol` [rad].
inline Eigen::Matrix3d extract_rotation(const Eigen::Matrix3d& F, const Eigen::Matrix3d& warm_start,
                                        double angle_tol = 1e-14, int max_iterations = 64) {
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

inline Eigen::Matrix2d extract_rotation(const Eigen::Matrix2d& F) {
    const double theta = std::atan2(F(1, 0) - F(0, 1), F(0, 0) + F(1, 1));
    const double c = std::cos(theta), s = std::sin(theta);
    Eigen::Matrix2d R;
    R << c, -s, s, c;
    return R;
}

}  // namespace xcut
