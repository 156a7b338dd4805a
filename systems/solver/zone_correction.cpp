#include "systems/solver/zone_correction.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>

namespace xcut {
namespace {

/// Calls f(column, value) for each stored entry of A's scalar row j (A symmetric, both triangles
/// stored: also column j's entries, by row).
template <class F>
void for_row(const LinearSystem& A, int j, F&& f) {
    const int node = j / 3, r = j % 3;
    for (int b = A.row_offset[node]; b < A.row_offset[node + 1]; ++b) {
        const double* v = A.value.data() + 9 * static_cast<size_t>(b) + 3 * r;
        const int c = 3 * A.column[b];
        f(c, v[0]), f(c + 1, v[1]), f(c + 2, v[2]);
    }
}

/// dofs[k] == j's k, or -1 (dofs increasing).
int slot_of(const std::vector<int>& dofs, int j) {
    const auto it = std::lower_bound(dofs.begin(), dofs.end(), j);
    return it != dofs.end() && *it == j ? static_cast<int>(it - dofs.begin()) : -1;
}

}  // namespace

bool build_zone_correction(const LinearSystem& A, const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask,
                           ZoneCorrection& out) {
    out.ok = false;
    out.dofs.clear();
    const int n = 3 * A.rows();
    for (const auto& t : block.coupling)
        if (t.col() < n && mask[t.col()] != 0.0) out.dofs.push_back(t.col());
    std::sort(out.dofs.begin(), out.dofs.end());
    out.dofs.erase(std::unique(out.dofs.begin(), out.dofs.end()), out.dofs.end());
    const int m = static_cast<int>(out.dofs.size());
    if (m == 0 || m > kZoneMaxDofs || block.rows == 0) return false;
    // s K_t on the zone: -s C_z^T H^-1 C_z, C_z the coupling's zone columns.
    Eigen::MatrixXd coupling = Eigen::MatrixXd::Zero(block.rows, m);
    for (const auto& t : block.coupling) {
        const int at = t.col() < n ? slot_of(out.dofs, t.col()) : -1;
        if (at >= 0) coupling(t.row(), at) += t.value();
    }
    Eigen::SparseMatrix<double> h(block.rows, block.rows);
    h.setFromTriplets(block.stiffness.begin(), block.stiffness.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> amplitudes(h);
    if (amplitudes.info() != Eigen::Success || (amplitudes.vectorD().array() <= 0.0).any()) return false;
    const Eigen::MatrixXd solved = amplitudes.solve(coupling);
    out.term = -stiff_scale * (coupling.transpose() * solved);
    out.term = 0.5 * (out.term + out.term.transpose()).eval();
    // S = A_zz + s K_t.
    Eigen::MatrixXd local = out.term;
    for (int k = 0; k < m; ++k)
        for_row(A, out.dofs[k], [&](int c, double v) {
            const int at = slot_of(out.dofs, c);
            if (at >= 0) local(k, at) += v;
        });
    out.local.compute(local);
    if (out.local.info() != Eigen::Success) return false;
    out.z1.resize(m), out.g.resize(m), out.zz.resize(m);
    return out.ok = true;
}

void zone_before_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& r1) {
    const int m = static_cast<int>(zc.dofs.size());
    for (int k = 0; k < m; ++k) zc.g[k] = r[zc.dofs[k]];
    zc.z1 = zc.local.solve(zc.g);
    // r1 = r - Â P z1: zero on the zone (S z1 = P^T r); off it, A's zone columns (K_t has zone rows
    // only), read as the zone's rows by symmetry.
    for (int k = 0; k < m; ++k) for_row(A, zc.dofs[k], [&](int c, double v) { r1[c] -= v * zc.z1[k]; });
    for (int j : zc.dofs) r1[j] = 0.0;
}

void zone_after_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    const int m = static_cast<int>(zc.dofs.size());
    for (int k = 0; k < m; ++k) z[zc.dofs[k]] += zc.z1[k];
    // g = P^T (r - Â z) = r_z - (A z)_z - s K_t z_z.
    for (int k = 0; k < m; ++k) {
        double acc = 0.0;
        for_row(A, zc.dofs[k], [&](int c, double v) { acc += v * z[c]; });
        zc.g[k] = acc, zc.zz[k] = z[zc.dofs[k]];
    }
    zc.g.noalias() += zc.term * zc.zz;
    for (int k = 0; k < m; ++k) zc.g[k] = r[zc.dofs[k]] - zc.g[k];
    zc.zz = zc.local.solve(zc.g);
    for (int k = 0; k < m; ++k) z[zc.dofs[k]] += zc.zz[k];
}

}  // namespace xcut
