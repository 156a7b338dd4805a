#pragma once
// The 10-node tetrahedron's shape functions and their gradients at barycentric coordinates L (VTK
// node order, cell type 24: corners 0-3, then the mid-edge nodes of kTet10Edges; Zienkiewicz, Taylor &
// Zhu, The Finite Element Method, 7th ed., §6.5):
//   N_i = L_i (2 L_i - 1),  grad N_i = (4 L_i - 1) g_i              (corners)
//   N_ab = 4 L_a L_b,       grad N_ab = 4 (L_a g_b + L_b g_a)         (mid-edge nodes)
// with g_i the linear element's constant shape gradients. Pure functions: the quadratic element's
// kernels (systems/kernels/quadratic_tet.h) and the output's drawing of its cut pieces
// (engine/io/clipped_cells.h) share them.
#include <Eigen/Core>
#include <array>

#include "components/nodes.h"
#include "components/quadratic_elements.h"

namespace xcut {

/// The 10 shape gradients at barycentric coordinates L, from the linear element's gradients g.
inline void tet10_gradients_at(const std::array<Vec3, 4>& g, const Eigen::Vector4d& L, std::array<Vec3, 10>& out) {
    for (int i = 0; i < 4; ++i) out[i] = (4.0 * L[i] - 1.0) * g[i];
    for (int k = 0; k < 6; ++k) {
        const int a = kTet10Edges[k][0], b = kTet10Edges[k][1];
        out[4 + k] = 4.0 * (L[a] * g[b] + L[b] * g[a]);
    }
}

/// The 10 shape functions at barycentric coordinates L: N_i = L_i (2 L_i - 1) at the corners and
/// N_ab = 4 L_a L_b on the edges [-].
inline std::array<double, 10> tet10_shapes(const Eigen::Vector4d& L) {
    std::array<double, 10> N;
    for (int i = 0; i < 4; ++i) N[i] = L[i] * (2.0 * L[i] - 1.0);
    for (int k = 0; k < 6; ++k) N[4 + k] = 4.0 * L[kTet10Edges[k][0]] * L[kTet10Edges[k][1]];
    return N;
}

/// The point at barycentric coordinates L of quadratic element `ids` (node positions x):
/// sum_j N_j(L) x_j [m].
inline Vec3 tet10_point(const std::array<int, 10>& ids, const Eigen::Vector4d& L, const Vec3* x) {
    const std::array<double, 10> N = tet10_shapes(L);
    Vec3 p = Vec3::Zero();
    for (int j = 0; j < 10; ++j) p += N[j] * x[ids[j]];
    return p;
}

}  // namespace xcut
