#include "engine/io/cell_stress.h"

#include <Eigen/SVD>

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
    const int t = w.quadratic.count() > 0 && e < w.mesh_elements ? w.quadratic.of_element[e] : -1;
    if (t >= 0) {
        // A quadratic element's strain is linear: its mean is the value at the centroid, where the
        // corners' gradients vanish and each mid-edge node's is g_a + g_b (components/quadratic_elements.h).
        const auto& q = w.quadratic.nodes[t];
        auto g = [&](int a) -> Vec3 {
            return a == 0 ? Vec3(-el.dm_inv[e].colwise().sum().transpose()) : Vec3(el.dm_inv[e].row(a - 1).transpose());
        };
        F.setZero();
        for (int k = 0; k < 6; ++k) F += x[q[4 + k]] * (g(kTet10Edges[k][0]) + g(kTet10Edges[k][1])).transpose();
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
