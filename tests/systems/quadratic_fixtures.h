#pragma once
// Shared by the quadratic tetrahedron's tests: a tetrahedron of no symmetry, its 10 nodes, closed
// forms of its integrals, and the element matrix from the kernel's blocks.
#include <Eigen/Core>
#include <Eigen/LU>
#include <array>

#include "systems/kernels/quadratic_tet.h"

namespace xcut::testing {

/// A tetrahedron of no symmetry [m].
inline std::array<Vec3, 4> corners() {
    return {Vec3(0.01, 0.02, -0.01), Vec3(0.13, 0.01, 0.02), Vec3(0.03, 0.11, 0.01), Vec3(0.02, 0.04, 0.15)};
}

inline Mat3 dm_inverse(const std::array<Vec3, 4>& X) {
    Mat3 D;
    for (int k = 0; k < 3; ++k) D.col(k) = X[k + 1] - X[0];
    return D.inverse();
}

inline double volume_of(const std::array<Vec3, 4>& X) {
    Mat3 D;
    for (int k = 0; k < 3; ++k) D.col(k) = X[k + 1] - X[0];
    return D.determinant() / 6.0;
}

/// The 10 nodes' rest positions: corners, then the edges' midpoints.
inline Tet10Vectors nodes_of(const std::array<Vec3, 4>& X) {
    Tet10Vectors out;
    for (int a = 0; a < 4; ++a) out[a] = X[a];
    for (int k = 0; k < 6; ++k) out[4 + k] = 0.5 * (X[kTet10Edges[k][0]] + X[kTet10Edges[k][1]]);
    return out;
}

/// Closed form of the integral of x_a x_b over a tetrahedron: V/20 (sum_i x_ia x_ib + sum x_ia sum x_ib).
inline double second_moment(const std::array<Vec3, 4>& X, int a, int b) {
    double ab = 0.0, sa = 0.0, sb = 0.0;
    for (const Vec3& p : X) ab += p[a] * p[b], sa += p[a], sb += p[b];
    return volume_of(X) / 20.0 * (ab + sa * sb);
}

inline const LameParameters kLame{3.0e4, 1.2e4};

/// The 30 x 30 element matrix from tet10_add_stiffness_block.
template <size_t P>
Eigen::MatrixXd tet10_matrix(const Tet10PointGradients<P>& G, const Mat3& R, double volume, const LameParameters& lame) {
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(30, 30);
    for (int j = 0; j < 10; ++j)
        for (int k = 0; k < 10; ++k) {
            Eigen::Matrix<double, 3, 3, Eigen::RowMajor> b = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>::Zero();
            tet10_add_stiffness_block(G, R, volume, lame, j, k, 1.0, b.data());
            K.block<3, 3>(3 * j, 3 * k) = b;
        }
    return K;
}

}  // namespace xcut::testing
