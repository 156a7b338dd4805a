#include "systems/solver/factor_augment.h"

#include <algorithm>

namespace xcut {
namespace {

/// Solves for the three columns of Y of new node `node` (its axes), appending them to g, and
/// fills their columns of C (rows: every new DOF). B's columns come from the node's own block row
/// (A is symmetric: A(i, node) = A(node, i)^T): B = A'_12 + E^T A'_22, C = A'_22 (jump basis).
/// One sparse solve for the three axes.
void solve_columns(const LinearSystem& A, int node, SparseForward<3>& solver, FactorAugment& g, Eigen::Ref<Eigen::MatrixXd> C) {
    const int base_nodes = g.base / 3;
    for (int b = A.row_offset[node]; b < A.row_offset[node + 1]; ++b) {
        const int i = A.column[b];
        const double* M = A.value.data() + 9 * b;  // M(c, r) = A(3 node + c, 3 i + r)
        for (int r = 0; r < 3; ++r) {
            int row = i < base_nodes ? 3 * i + r : -1;
            if (i >= base_nodes) {
                const int q = 3 * (i - base_nodes) + r;
                for (int c = 0; c < 3; ++c) C(q, c) = M[3 * c + r];
                row = g.parent[q];
            }
            if (row < 0) continue;
            const double v[3] = {M[r], M[3 + r], M[6 + r]};
            solver.add(row, v);
        }
    }
    solver.solve();
    for (int c = 0; c < 3; ++c) {
        for (int j : solver.reach())
            if (solver.x(j)[c] != 0.0) g.y_row.push_back(j), g.y_value.push_back(solver.x(j)[c]);
        g.y_start.push_back(static_cast<int>(g.y_row.size()));
    }
    solver.clear();
}


}  // namespace

bool extend_augment(const LinearSystem& A, const LowerFactor& lf, std::vector<int> parent, FactorAugment& g) {
    const int base = lf.rows(), m = static_cast<int>(parent.size());
    const bool keeps = g.ok && g.base == base && g.columns() <= m &&
                       std::equal(g.parent.begin(), g.parent.end(), parent.begin());
    if (!keeps) g.y_start.assign(1, 0), g.y_row.clear(), g.y_value.clear(), g.S.resize(0, 0);
    const int kept = keeps ? g.columns() : 0;
    g.topology = A.topology, g.base = base, g.parent = std::move(parent), g.ok = false;
    Eigen::MatrixXd C(m, m - kept);
    C.setZero();
    SparseForward<3> solver(lf);
    for (int k = kept; k < m; k += 3) solve_columns(A, base / 3 + k / 3, solver, g, C.middleCols(k - kept, 3));
    g.S.conservativeResize(m, m);
    Eigen::VectorXd w = Eigen::VectorXd::Zero(base);
    for (int k = kept; k < m; ++k) {  // S's rows and columns of the new DOFs: C - Y^T Y
        for (int p = g.y_start[k]; p < g.y_start[k + 1]; ++p) w[g.y_row[p]] = g.y_value[p];
        for (int q = 0; q <= k; ++q) g.S(q, k) = g.S(k, q) = C(q, k - kept) - g.column_dot(q, w);
        for (int p = g.y_start[k]; p < g.y_start[k + 1]; ++p) w[g.y_row[p]] = 0.0;
    }
    if (m == 0) return g.ok = true;  // a split among existing phantoms: the old factor alone
    g.schur.compute(g.S);
    return g.ok = g.schur.info() == Eigen::Success;
}

}  // namespace xcut
