#pragma once
// Pure kernels of the corotational quadratic tetrahedron (10 nodes, straight edges; Zienkiewicz,
// Taylor & Zhu, The Finite Element Method, 7th ed., §6.5 for the shape functions; the corotation of
// Müller & Gross 2004 with one rotation per element, from the corner tetrahedron's deformation
// gradient, as the linear element's).
//
// Node order is VTK's (cell type 24): corners 0-3, then the mid-edge nodes of the edges
// (0,1) (1,2) (0,2) (0,3) (1,3) (2,3). With L_i the barycentric coordinates and g_i = grad L_i the
// linear element's constant shape gradients (rows of Dm^-1, g_0 = -sum):
//   N_i = L_i (2 L_i - 1),  grad N_i = (4 L_i - 1) g_i              (corners)
//   N_ab = 4 L_a L_b,       grad N_ab = 4 (L_a g_b + L_b g_a)         (mid-edge nodes)
// The strain is linear in the element, the stiffness integrand quadratic: the 4-point rule of degree
// 2 (Keast 1986; points a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20, weights V/4) integrates it
// exactly. The corotated stress at each point is sigma = lambda tr(eps) I + 2 mu eps with
// eps = sym(R^T F) - I, F = sum_j x_j grad N_j^T; the forces f_j = -sum_q w_q R sigma_q grad N_j(q).
//
// Why one rotation per element, not per point: the rotation's change within a straight-edged element
// is of the order of the strain's, which the linear law already neglects; per-point rotations would
// make K depend on four polar decompositions for no gain in the small-strain regime the model is for.
// One side of a cut element takes the polar factor of its F's mean over the side instead of its
// corners' (quadratic_rotation, systems/kernels/quadratic_elastic.h): its corners may be phantoms.
//
// Lumped mass: HRZ (Hinton, Rock & Zienkiewicz 1976): the consistent mass's diagonal scaled to the
// element's mass, rho V / 36 to each corner and 4 rho V / 27 to each mid-edge node. The row-sum
// lumping would give the corners -rho V / 20. HRZ keeps the mass's total and centre.
#include <Eigen/Core>
#include <array>

#include "components/nodes.h"
#include "components/quadratic_elements.h"
#include "engine/tet10_shapes.h"
#include "systems/kernels/corotational_kernel.h"

namespace xcut {

// HRZ lumped mass shares: kTet10CornerMass, kTet10EdgeMass, kTri6CornerMass, kTri6EdgeMass
// (components/quadratic_elements.h).

using Tet10Vectors = std::array<Vec3, 10>;

/// The shape gradients of the 10 nodes at each point of a quadrature rule [1/m]: grad[q][j], with
/// the points' weights as fractions of the element's rest volume [-]. P bounds the points: 4 for
/// Keast's rule over the whole element, more for one side of a cut element
/// (systems/kernels/tet10_side_rule.h).
template <size_t P>
struct Tet10PointGradients {
    int count = 0;
    std::array<std::array<Vec3, 10>, P> grad;
    std::array<double, P> weight;
    /// A 6-node triangle's (2D, the xy plane; tri3_gradients): the deformation gradient's z column is
    /// e_z, so the out-of-plane strain is 0 and the plane-stress Lamé parameters give the in-plane law.
    bool planar = false;
};
using Tet10Gradients = Tet10PointGradients<4>;

/// The rule's point count and point q's weight: constants for the whole element's 4 points (so its
/// loops unroll; the same values as tet10_gradients stores).
template <size_t P>
XCUT_INLINE int tet10_points(const Tet10PointGradients<P>& G) {
    if constexpr (P == 4) return 4;
    else return G.count;
}
template <size_t P>
XCUT_INLINE double tet10_weight(const Tet10PointGradients<P>& G, int q) {
    if constexpr (P == 4) return 0.25;
    else return G.weight[q];
}

/// Barycentric coordinate L_i of quadrature point q (Keast's degree-2 rule).
inline double tet10_point_coordinate(int q, int i) {
    constexpr double a = 0.5854101966249685, b = 0.1381966011250105;
    return q == i ? a : b;
}


/// The linear element's shape gradients g_j from its Dm^-1 [1/m].
inline std::array<Vec3, 4> tet4_gradients(const Mat3& dm_inv) {
    std::array<Vec3, 4> g;
    for (int j = 0; j < 4; ++j) g[j] = shape_gradient<3>(dm_inv, j);
    return g;
}

/// The 6-node triangle (2D, the xy plane) as a 10-node tetrahedron without its fourth corner: the
/// triangle's corner gradients (rows of its Dm^-1, g_0 = -g_1 - g_2) and g_3 = 0. With L_3 = 0 at
/// every point, N_3 and the shape functions of the edges to corner 3 vanish with their gradients, and
/// the other six are the triangle's N_i = L_i (2 L_i - 1), N_ab = 4 L_a L_b (VTK's cell type 22:
/// corners 0-2, then the edges (0,1) (1,2) (2,0) = kTet10Edges' first three).
inline std::array<Vec3, 4> tri3_gradients(const Mat3& dm_inv) {
    std::array<Vec3, 4> g;
    for (int j = 1; j < 3; ++j) g[j] = Vec3(dm_inv(j - 1, 0), dm_inv(j - 1, 1), 0.0);
    g[0] = -(g[1] + g[2]);
    g[3] = Vec3::Zero();
    return g;
}

/// The gradients at Keast's 4 points (weights 1/4) from the linear element's Dm^-1.
inline Tet10Gradients tet10_gradients(const Mat3& dm_inv) {
    const std::array<Vec3, 4> g = tet4_gradients(dm_inv);
    Tet10Gradients out;
    out.count = 4;
    for (int q = 0; q < 4; ++q) {
        Eigen::Vector4d L;
        for (int i = 0; i < 4; ++i) L[i] = tet10_point_coordinate(q, i);
        tet10_gradients_at(g, L, out.grad[q]);
        out.weight[q] = 0.25;
    }
    return out;
}



/// sum_j v_j grad N_j(q)^T.
template <size_t P>
XCUT_INLINE Mat3 tet10_gradient_of(const Tet10Vectors& v, const Tet10PointGradients<P>& G, int q) {
    Mat3 out = Mat3::Zero();
    for (int j = 0; j < 10; ++j) out.noalias() += v[j] * G.grad[q][j].transpose();
    return out;
}

/// The element's deformation gradient at point q from its node positions: sum_j x_j grad N_j^T, with
/// e_z e_z^T added for a triangle (its nodes lie in the xy plane).
template <size_t P>
XCUT_INLINE Mat3 tet10_deformation_gradient(const std::array<Vec3, 10>& x, const Tet10PointGradients<P>& G, int q) {
    Mat3 F = tet10_gradient_of(x, G, q);
    if (G.planar) F(2, 2) += 1.0;
    return F;
}

/// out_j = scale sum_q w_q R sigma_q grad N_j(q) (the rule's weights w_q; V in scale).
template <size_t P>
XCUT_INLINE void tet10_scatter(const Mat3& R, const std::array<Mat3, P>& sigma, const Tet10PointGradients<P>& G,
                               double scale, Tet10Vectors& out) {
    std::array<Mat3, P> Q;
    for (int q = 0; q < tet10_points(G); ++q) Q[q] = (tet10_weight(G, q) * scale) * R * sigma[q];
    for (int j = 0; j < 10; ++j) {
        Vec3 s = Vec3::Zero();
        for (int q = 0; q < tet10_points(G); ++q) s.noalias() += Q[q] * G.grad[q][j];
        out[j] = s;
    }
}

/// The rule's weight sum W [-] (1 for the whole element; a side's fraction) and
/// rbar_j = sum_q w_q R grad N_j(q) [1/m]: the mean volumetric strain is theta = sum_j rbar_j . u_j / W.
template <size_t P>
inline double tet10_mean_gradients(const Tet10PointGradients<P>& G, const Mat3& R, std::array<Vec3, 10>& rbar) {
    double W = 0.0;
    for (int j = 0; j < 10; ++j) rbar[j].setZero();
    for (int q = 0; q < tet10_points(G); ++q) {
        W += tet10_weight(G, q);
        for (int j = 0; j < 10; ++j) rbar[j] += tet10_weight(G, q) * (R * G.grad[q][j]);
    }
    return W;
}

/// Adds lame.lambda_mean theta I to every point's stress, theta = sum_q w_q tr(H_q) / W the mean of
/// tr(H) over the rule (the constant pressure of P2-P0: the volumetric strain projected onto
/// constants, Hughes's B-bar (1980), equivalent to the mixed element with its pressure condensed,
/// Malkus & Hughes 1978); returns theta [-]. Nothing when lambda_mean is 0 (the bits stay).
template <size_t P>
XCUT_INLINE double tet10_add_mean_pressure(const std::array<double, P>& trace, const Tet10PointGradients<P>& G,
                                           const LameParameters& lame, std::array<Mat3, P>& sigma, double& W) {
    W = 0.0;
    if (lame.lambda_mean == 0.0) return 0.0;
    double theta = 0.0;
    for (int q = 0; q < tet10_points(G); ++q) theta += tet10_weight(G, q) * trace[q], W += tet10_weight(G, q);
    theta /= W;
    for (int q = 0; q < tet10_points(G); ++q) sigma[q].diagonal().array() += lame.lambda_mean * theta;
    return theta;
}

/// Elastic forces f_j = -sum_q w_q V R sigma_q grad N_j(q) at positions x [N]; returns the strain
/// energy [J]. `volume`: the element's rest volume (times its weight) [m^3]. With lambda_mean, the
/// volumetric energy is lambda_mean V W theta^2 / 2 on the mean theta.
template <size_t P>
inline double tet10_forces(const Tet10Vectors& x, const Tet10PointGradients<P>& G, const Mat3& R, double volume,
                           const LameParameters& lame, Tet10Vectors& force) {
    std::array<Mat3, P> sigma;
    std::array<double, P> trace;
    double energy = 0.0;
    for (int q = 0; q < tet10_points(G); ++q) {
        const Mat3 H = R.transpose() * tet10_deformation_gradient(x, G, q) - Mat3::Identity();
        sigma[q] = linear_stress<3>(H, lame);
        trace[q] = H.trace();
        const Mat3 eps = 0.5 * (H + H.transpose());
        energy += tet10_weight(G, q) * volume * (lame.mu * eps.squaredNorm() + 0.5 * lame.lambda * eps.trace() * eps.trace());
    }
    double W = 0.0;
    const double theta = tet10_add_mean_pressure(trace, G, lame, sigma, W);
    if (lame.lambda_mean != 0.0) energy += 0.5 * lame.lambda_mean * volume * W * theta * theta;
    tet10_scatter(R, sigma, G, -volume, force);
    return energy;
}

/// Stiffness action out_j = sum_k K_jk p_k (rotation frozen) [N].
template <size_t P>
inline void tet10_stiffness_product(const Tet10Vectors& p, const Tet10PointGradients<P>& G, const Mat3& R,
                                    double volume, const LameParameters& lame, Tet10Vectors& out) {
    std::array<Mat3, P> sigma;
    std::array<double, P> trace;
    for (int q = 0; q < tet10_points(G); ++q) {
        const Mat3 H = R.transpose() * tet10_gradient_of(p, G, q);
        sigma[q] = linear_stress<3>(H, lame);
        trace[q] = H.trace();
    }
    double W = 0.0;
    tet10_add_mean_pressure(trace, G, lame, sigma, W);
    tet10_scatter(R, sigma, G, volume, out);
}

/// Adds block (j, k) of the element stiffness, scaled, to the row-major 3x3 `block`: per point the
/// linear element's block (add_corotational_stiffness_block) with the rotated gradients R grad N;
/// with lambda_mean, (lambda_mean V / W) rbar_j rbar_k^T besides.
template <size_t P>
inline void tet10_add_stiffness_block(const Tet10PointGradients<P>& G, const Mat3& R, double volume,
                                      const LameParameters& lame, int j, int k, double scale, double* block) {
    for (int q = 0; q < tet10_points(G); ++q) {
        const double w = tet10_weight(G, q) * volume * scale;
        const Vec3 rj = R * G.grad[q][j], rk = R * G.grad[q][k];
        add_corotational_stiffness_block((w * lame.lambda) * rj, (w * lame.mu) * rj, rk, 3, block);
    }
    if (lame.lambda_mean == 0.0) return;
    std::array<Vec3, 10> rbar;
    const double W = tet10_mean_gradients(G, R, rbar);
    add_corotational_stiffness_block((lame.lambda_mean * volume * scale / W) * rbar[j], Vec3::Zero(), rbar[k], 3, block);
}

/// Diagonal of the element stiffness: node j, axis c: sum_q w_q V (mu |g|^2 + (lambda + mu) (R g)_c^2),
/// and (lambda_mean V / W) (rbar_j)_c^2.
template <size_t P>
inline void tet10_stiffness_diagonal(const Tet10PointGradients<P>& G, const Mat3& R, double volume,
                                     const LameParameters& lame, Tet10Vectors& out) {
    for (int j = 0; j < 10; ++j) {
        out[j].setZero();
        for (int q = 0; q < tet10_points(G); ++q) {
            const Vec3 rg = R * G.grad[q][j];
            out[j] += tet10_weight(G, q) * volume * (lame.mu * rg.squaredNorm() * Vec3::Ones() + (lame.lambda + lame.mu) * rg.cwiseAbs2());
        }
    }
    if (lame.lambda_mean == 0.0) return;
    std::array<Vec3, 10> rbar;
    const double W = tet10_mean_gradients(G, R, rbar);
    for (int j = 0; j < 10; ++j) out[j] += (lame.lambda_mean * volume / W) * rbar[j].cwiseAbs2();
}

}  // namespace xcut
