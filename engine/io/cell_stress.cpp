#include "engine/io/cell_stress.h"

#include <Eigen/SVD>

#include "engine/quadratic_setup.h"
#include "engine/tet10_shapes.h"

namespace xcut {

namespace {

/// The rotation of F's polar decomposition (SVD, reflection removed).
Mat3 polar_rotation(const Mat3& F) {
    const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 U = svd.matrixU();
    if ((U * svd.matrixV().transpose()).determinant() < 0.0) U.col(2) *= -1.0;
    return U * svd.matrixV().transpose();
}

}  // namespace

Mat3 cell_cauchy_stress(const World& w, int e) {
    const Elements& el = w.elements;
    const Vec3* x = w.nodes.position.data();
    const auto& c = el.nodes[e];
    Mat3 Ds = Mat3::Identity();  // 2D: the third column stays e_z, as Dm^-1's
    for (int k = 0; k < el.dim; ++k) Ds.col(k) = x[c[k + 1]] - x[c[0]];
    Mat3 F = Ds * el.dm_inv[e];
    const Mat3 R = polar_rotation(F);  // a quadratic element's too: the corners', as the ForceSystem's
    const int t = quadratic_entry(w, e);
    if (t >= 0) {
        // A quadratic element's strain is linear: its mean over the element is its value at the
        // centroid, and over one side of a cut element its value at the side's centroid (its rule
        // integrates L exactly: L_c = sum_q w_q L_q / sum_q w_q).
        const QuadraticElements& q = w.quadratic;
        const int r = t < static_cast<int>(q.side_rule.size()) ? q.side_rule[t] : -1;
        Eigen::Vector4d L = q.planar ? Eigen::Vector4d(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.0) : Eigen::Vector4d::Constant(0.25);
        if (r >= 0 && q.side_rules[r].count > 0) {
            const TetSideRule& rule = q.side_rules[r];
            double sum = 0.0;
            L.setZero();
            for (int k = 0; k < rule.count; ++k) L += rule.weight[k] * rule.L[k], sum += rule.weight[k];
            if (sum > 0.0) L /= sum;
        }
        std::array<Vec3, 4> g;  // the linear element's shape gradients: rows of Dm^-1, g_0 = -sum
        for (int a = 1; a < 4; ++a) g[a] = el.dm_inv[e].row(a - 1).transpose();
        if (q.planar) g[1].z() = g[2].z() = 0.0, g[3].setZero();  // a 6-node triangle (quadratic_tet.h, tri3_gradients)
        g[0] = -(g[1] + g[2] + g[3]);
        std::array<Vec3, 10> grad;
        tet10_gradients_at(g, L, grad);
        F.setZero();
        for (int j = 0; j < 10; ++j) F += x[q.nodes[t][j]] * grad[j].transpose();
        if (q.planar) F(2, 2) = 1.0;
    }
    const Mat3 eps = 0.5 * (R.transpose() * F + F.transpose() * R) - Mat3::Identity();
    const Material& m = w.materials.list[el.material[e]];
    const double mu = m.mu(), lambda = el.dim == 3 ? m.lambda() : m.lambda_plane_stress();
    Mat3 s = 2.0 * mu * eps;
    if (el.dim == 3) {
        s += lambda * eps.trace() * Mat3::Identity();
    } else {
        s.topLeftCorner<2, 2>() += lambda * eps.topLeftCorner<2, 2>().trace() * Eigen::Matrix2d::Identity();
        s.row(2).setZero(), s.col(2).setZero();
    }
    return R * s * R.transpose();
}

double von_mises(const Mat3& sigma) {
    const Mat3 dev = sigma - sigma.trace() / 3.0 * Mat3::Identity();
    return std::sqrt(1.5 * dev.cwiseProduct(dev).sum());
}

}  // namespace xcut
