#pragma once
// Pure kernels of the corotational linear element (paper App. B, eq. 10; Müller & Gross 2004;
// Nesme, Payan & Faure 2005): f_i = R sum_j K_ij (R^T p_j - p0_j), evaluated without forming K.
//
// With F = Ds Dm^-1 the deformation gradient and g_j the rest shape gradients (rows of Dm^-1,
// g_0 = -sum), the corotated small strain is eps = sym(R^T F) - I and the stress
// sigma = lambda tr(eps) I + 2 mu eps. The nodal forces are f_j = -V R sigma g_j. The stiffness
// action on a velocity-like field p (rotation frozen) is the same map applied to H = R^T P with
// P = sum_j p_j g_j^T, without the identity shift: about 150 flops per tetrahedron, against 288
// multiply-adds and 1152 bytes for a stored 12x12 block.
//
// D = 3: tetrahedra. D = 2: triangles in the xy plane under plane stress (the caller passes the
// plane-stress lambda and V = area x thickness).
#include <Eigen/Core>
#include <array>

#include "components/nodes.h"

// Hot kernels: force inlining so the per-element loop compiles to one straight block.
#define XCUT_INLINE inline __attribute__((always_inline))

namespace xcut {

template <int D>
using MatD = Eigen::Matrix<double, D, D>;
template <int D>
using VecD = Eigen::Matrix<double, D, 1>;

struct LameParameters {
    double lambda;  ///< [Pa], at every quadrature point
    double mu;      ///< [Pa]
    /// [Pa]: lambda on the element's mean volumetric strain instead (a quadratic element with a
    /// constant pressure, systems/kernels/quadratic_tet.h); the linear element's strain is constant,
    /// so it has no use for it.
    double lambda_mean = 0.0;
};

/// Edge matrix [x1-x0, x2-x0(, x3-x0)] of an element's nodes.
template <int D>
XCUT_INLINE MatD<D> edge_matrix(const std::array<Vec3, 4>& x) {
    MatD<D> Ds;
    for (int c = 0; c < D; ++c) Ds.col(c) = (x[c + 1] - x[0]).template head<D>();
    return Ds;
}

/// Stress of a local displacement gradient H: sigma = lambda tr(eps) I + 2 mu eps, eps = sym(H).
template <int D>
XCUT_INLINE MatD<D> linear_stress(const MatD<D>& H, const LameParameters& lame) {
    const MatD<D> eps = 0.5 * (H + H.transpose());
    return lame.lambda * eps.trace() * MatD<D>::Identity() + 2.0 * lame.mu * eps;
}

/// Scatters V R sigma g_j to the element's nodes: out_j = scale * R sigma g_j, with g_0 = -sum.
template <int D>
XCUT_INLINE void scatter_stress(const MatD<D>& R, const MatD<D>& sigma, const MatD<D>& dm_inv, double scale,
                           std::array<Vec3, 4>& out) {
    const MatD<D> Q = scale * R * sigma * dm_inv.transpose();  // columns: nodes 1..D
    VecD<D> sum = VecD<D>::Zero();
    for (int c = 0; c < D; ++c) {
        out[c + 1].setZero();
        out[c + 1].template head<D>() = Q.col(c);
        sum += Q.col(c);
    }
    out[0].setZero();
    out[0].template head<D>() = -sum;
}

/// Elastic forces f_j = -V R sigma g_j and strain energy V (mu eps:eps + lambda/2 tr(eps)^2) [J].
template <int D>
XCUT_INLINE double corotational_forces(const std::array<Vec3, 4>& x, const MatD<D>& dm_inv, const MatD<D>& R,
                                  double volume, const LameParameters& lame, std::array<Vec3, 4>& force) {
    const MatD<D> F = edge_matrix<D>(x) * dm_inv;
    const MatD<D> H = R.transpose() * F - MatD<D>::Identity();
    const MatD<D> sigma = linear_stress<D>(H, lame);
    scatter_stress<D>(R, sigma, dm_inv, -volume, force);
    const MatD<D> eps = 0.5 * (H + H.transpose());
    return volume * (lame.mu * eps.squaredNorm() + 0.5 * lame.lambda * eps.trace() * eps.trace());
}

/// The strain energy alone, as corotational_forces returns it [J] (the energy check's, at positions
/// the step has not linearized about).
template <int D>
XCUT_INLINE double corotational_energy(const MatD<D>& F, const MatD<D>& R, double volume, const LameParameters& lame) {
    const MatD<D> H = R.transpose() * F - MatD<D>::Identity();
    const MatD<D> eps = 0.5 * (H + H.transpose());
    return volume * (lame.mu * eps.squaredNorm() + 0.5 * lame.lambda * eps.trace() * eps.trace());
}

/// Stiffness action out_j = sum_k K_jk p_k = V R sigma(R^T P) g_j (K positive semi-definite).
template <int D>
XCUT_INLINE void corotational_stiffness_product(const std::array<Vec3, 4>& p, const MatD<D>& dm_inv,
                                           const MatD<D>& R, double volume, const LameParameters& lame,
                                           std::array<Vec3, 4>& out) {
    const MatD<D> H = R.transpose() * (edge_matrix<D>(p) * dm_inv);
    scatter_stress<D>(R, linear_stress<D>(H, lame), dm_inv, volume, out);
}

/// Rest shape gradient g_j of node j (rows of Dm^-1; g_0 = -sum of the others).
template <int D>
XCUT_INLINE VecD<D> shape_gradient(const MatD<D>& dm_inv, int j) {
    return j == 0 ? VecD<D>(-dm_inv.transpose() * VecD<D>::Ones()) : VecD<D>(dm_inv.row(j - 1).transpose());
}

/// Block (j, k) of the element stiffness, the matrix whose action corotational_stiffness_product
/// computes: K_jk = V R (lambda g_j g_k^T + mu g_k g_j^T + mu (g_j . g_k) I) R^T [N/m]. From
/// sigma(H) g_j with H = R^T p_k g_k^T: tr(eps) = g_k . R^T p_k, eps g_j = (R^T p_k (g_k . g_j) +
/// g_k (R^T p_k . g_j)) / 2. R is a rotation (R I R^T = I), so with the rotated gradients r = R g:
/// K_jk = V (lambda r_j r_k^T + mu r_k r_j^T + mu (r_j . r_k) I). In 2D the gradients have z = 0
/// and the z row and column of the block are left 0. Adds K_jk to the row-major 3x3 `block`, given
/// lambda_rj = V lambda r_j and mu_rj = V mu r_j (made once per row j): 21 flops a block.
XCUT_INLINE void add_corotational_stiffness_block(const Vec3& lambda_rj, const Vec3& mu_rj, const Vec3& rk, int dim,
                                                  double* block) {
    // Each entry read, added to and written once (the diagonal term folded in): a second pass over
    // the diagonal would wait on the first one's stores.
    const double diagonal = mu_rj.dot(rk), diagonal_z = dim == 3 ? diagonal : 0.0;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            block[3 * r + c] += lambda_rj[r] * rk[c] + rk[r] * mu_rj[c] + (r != c ? 0.0 : r < 2 ? diagonal : diagonal_z);
}

/// Diagonal of the element stiffness: node j, axis k: V (mu |g_j|^2 + (lambda + mu) (R g_j)_k^2).
template <int D>
inline void corotational_stiffness_diagonal(const MatD<D>& dm_inv, const MatD<D>& R, double volume,
                                            const LameParameters& lame, std::array<Vec3, 4>& out) {
    for (int j = 0; j <= D; ++j) {
        VecD<D> g;
        if (j == 0) {
            g = -dm_inv.transpose() * VecD<D>::Ones();
        } else {
            g = dm_inv.row(j - 1).transpose();
        }
        const VecD<D> rg = R * g;
        out[j].setZero();
        out[j].template head<D>() =
            volume * (lame.mu * g.squaredNorm() * VecD<D>::Ones() + (lame.lambda + lame.mu) * rg.cwiseAbs2());
    }
}

}  // namespace xcut
