#include "systems/solver/zone_correction.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>

namespace xcut {
namespace {

/// out[k] = (A z)[dofs[k]]: the zone's rows of A times z (A symmetric, both triangles stored).
void zone_rows_times(const LinearSystem& A, const std::vector<int>& dofs, const Eigen::VectorXd& z, Eigen::VectorXd& out) {
    for (size_t k = 0; k < dofs.size(); ++k) {
        const int node = dofs[k] / 3, r = dofs[k] % 3;
        double acc = 0.0;
        for (int b = A.row_offset[node]; b < A.row_offset[node + 1]; ++b) {
            const double* v = A.value.data() + 9 * static_cast<size_t>(b) + 3 * r;
            const int c = 3 * A.column[b];
            acc += v[0] * z[c] + v[1] * z[c + 1] + v[2] * z[c + 2];
        }
        out[static_cast<Eigen::Index>(k)] = acc;
    }
}

}  // namespace

bool build_zone_correction(const LinearSystem& A, const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask,
                           ZoneCorrection& out) {
    for (int j : out.dofs) out.slot[j] = -1;
    out.ok = false;
    out.dofs.clear();
    const int n = 3 * A.rows();
    if (static_cast<int>(out.slot.size()) != n) out.slot.assign(n, -1);
    for (const auto& t : block.coupling)
        if (t.col() < n && mask[t.col()] != 0.0) out.dofs.push_back(t.col());
    std::sort(out.dofs.begin(), out.dofs.end());
    out.dofs.erase(std::unique(out.dofs.begin(), out.dofs.end()), out.dofs.end());
    const int m = static_cast<int>(out.dofs.size());
    if (m == 0 || m > kZoneMaxDofs || block.rows == 0) return false;
    for (int k = 0; k < m; ++k) out.slot[out.dofs[k]] = k;
    // s K_t on the zone: -s C_z^T H^-1 C_z, C_z the coupling's zone columns.
    Eigen::MatrixXd coupling = Eigen::MatrixXd::Zero(block.rows, m);
    for (const auto& t : block.coupling)
        if (t.col() < n && out.slot[t.col()] >= 0) coupling(t.row(), out.slot[t.col()]) += t.value();
    Eigen::SparseMatrix<double> h(block.rows, block.rows);
    h.setFromTriplets(block.stiffness.begin(), block.stiffness.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> amplitudes(h);
    if (amplitudes.info() != Eigen::Success || (amplitudes.vectorD().array() <= 0.0).any()) return false;
    const Eigen::MatrixXd solved = amplitudes.solve(coupling);
    out.term = -stiff_scale * (coupling.transpose() * solved);
    out.term = 0.5 * (out.term + out.term.transpose()).eval();
    // S = A_zz + s K_t.
    Eigen::MatrixXd local = out.term;
    for (int k = 0; k < m; ++k) {
        const int node = out.dofs[k] / 3, r = out.dofs[k] % 3;
        for (int b = A.row_offset[node]; b < A.row_offset[node + 1]; ++b)
            for (int c = 0; c < 3; ++c) {
                const int at = out.slot[3 * A.column[b] + c];
                if (at >= 0) local(k, at) += A.value[9 * static_cast<size_t>(b) + 3 * r + c];
            }
    }
    out.local.compute(local);
    if (out.local.info() != Eigen::Success) return false;
    out.z1.resize(m), out.g.resize(m);
    return out.ok = true;
}

void zone_before_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& r1) {
    const int m = static_cast<int>(zc.dofs.size());
    for (int k = 0; k < m; ++k) zc.g[k] = r[zc.dofs[k]];
    zc.z1 = zc.local.solve(zc.g);
    // r1 = r - Â P z1: zero on the zone (S z1 = P^T r); off it, A's zone columns (K_t has zone rows only).
    for (int k = 0; k < m; ++k) {
        const int node = zc.dofs[k] / 3, r0 = zc.dofs[k] % 3;
        for (int b = A.row_offset[node]; b < A.row_offset[node + 1]; ++b) {
            const double* v = A.value.data() + 9 * static_cast<size_t>(b) + 3 * r0;  // row dofs[k] = column, by symmetry
            const int c = 3 * A.column[b];
            for (int q = 0; q < 3; ++q) r1[c + q] -= v[q] * zc.z1[k];
        }
    }
    for (int j : zc.dofs) r1[j] = 0.0;
}

void zone_after_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    const int m = static_cast<int>(zc.dofs.size());
    for (int k = 0; k < m; ++k) z[zc.dofs[k]] += zc.z1[k];
    // g = P^T (r - Â z) = r_z - (A z)_z - s K_t z_z.
    zone_rows_times(A, zc.dofs, z, zc.g);
    Eigen::VectorXd zz(m);
    for (int k = 0; k < m; ++k) zz[k] = z[zc.dofs[k]];
    zc.g.noalias() += zc.term * zz;
    for (int k = 0; k < m; ++k) zc.g[k] = r[zc.dofs[k]] - zc.g[k];
    zz = zc.local.solve(zc.g);
    for (int k = 0; k < m; ++k) z[zc.dofs[k]] += zz[k];
}

}  // namespace xcut
