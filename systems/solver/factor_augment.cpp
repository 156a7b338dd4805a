#include "systems/solver/factor_augment.h"

#include <algorithm>

namespace xcut {
namespace {

/// Solves for the three columns of Y of new node `node` (its axes), appending them to g, and
/// fills their columns of C (rows: every new DOF). B's columns come from the node's own block row
/// (A is symmetric: A(i, node) = A(node, i)^T): B = A'_12 + E^T A'_22, C = A'_22 (jump basis).
/// The solve touches only the rows the entries reach up the elimination tree (Gilbert & Peierls
/// 1988: the pattern of L's column j lies on j's path), one reach for the three axes.
class ColumnSolver {
public:
    ColumnSolver(const LowerFactor& lf) : lf_(lf), where_(lf.rows()), x_(3 * lf.rows(), 0.0), marked_(lf.rows(), 0) {
        for (int k = 0; k < lf.rows(); ++k) where_[lf.perm[k]] = k;
    }

    void solve(const LinearSystem& A, int node, FactorAugment& g, Eigen::Ref<Eigen::MatrixXd> C) {
        const int base_nodes = g.base / 3;
        reach_.clear();
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
                const int at = where_[row];
                for (int c = 0; c < 3; ++c) x_[3 * at + c] += M[3 * c + r];
                for (int j = at; j != -1 && !marked_[j]; j = lf_.etree_parent(j)) marked_[j] = 1, reach_.push_back(j);
            }
        }
        std::sort(reach_.begin(), reach_.end());  // a child before its parent: a topological order
        for (int j : reach_) lf_.eliminate_column<3>(j, x_.data());
        for (int c = 0; c < 3; ++c) {
            for (int j : reach_)
                if (x_[3 * j + c] != 0.0) g.y_row.push_back(j), g.y_value.push_back(x_[3 * j + c]);
            g.y_start.push_back(static_cast<int>(g.y_row.size()));
        }
        for (int j : reach_) x_[3 * j] = x_[3 * j + 1] = x_[3 * j + 2] = 0.0, marked_[j] = 0;
    }

private:
    const LowerFactor& lf_;
    std::vector<int> where_;  ///< row of A -> row of P A P^T
    std::vector<double> x_;
    std::vector<char> marked_;
    std::vector<int> reach_;
};

/// Y_q . v over column q's entries (v dense, in the factor's order).
double column_dot(const FactorAugment& g, int q, const Eigen::VectorXd& v) {
    double s = 0.0;
    for (int p = g.y_start[q]; p < g.y_start[q + 1]; ++p) s += g.y_value[p] * v[g.y_row[p]];
    return s;
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
    ColumnSolver columns(lf);
    for (int k = kept; k < m; k += 3) columns.solve(A, base / 3 + k / 3, g, C.middleCols(k - kept, 3));
    g.S.conservativeResize(m, m);
    Eigen::VectorXd w = Eigen::VectorXd::Zero(base);
    for (int k = kept; k < m; ++k) {  // S's rows and columns of the new DOFs: C - Y^T Y
        for (int p = g.y_start[k]; p < g.y_start[k + 1]; ++p) w[g.y_row[p]] = g.y_value[p];
        for (int q = 0; q <= k; ++q) g.S(q, k) = g.S(k, q) = C(q, k - kept) - column_dot(g, q, w);
        for (int p = g.y_start[k]; p < g.y_start[k + 1]; ++p) w[g.y_row[p]] = 0.0;
    }
    if (m == 0) return g.ok = true;  // a split among existing phantoms: the old factor alone
    g.schur.compute(g.S);
    return g.ok = g.schur.info() == Eigen::Success;
}

void apply_augment(const LowerFactor& lf, const FactorAugment& g, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    const int base = g.base, m = g.columns();
    Eigen::VectorXd g1 = r.head(base);  // T^T r: each new DOF's residual also on its mesh node's
    for (int q = 0; q < m; ++q)
        if (g.parent[q] >= 0) g1[g.parent[q]] += r[base + q];
    Eigen::VectorXd t(base);
    for (int k = 0; k < base; ++k) t[k] = g1[lf.perm[k]];
    lf.forward(t);
    Eigen::VectorXd a(m);
    for (int q = 0; q < m; ++q) a[q] = r[base + q] - column_dot(g, q, t);
    if (m > 0) a = g.schur.solve(a);
    for (int q = 0; q < m; ++q)
        for (int p = g.y_start[q]; p < g.y_start[q + 1]; ++p) t[g.y_row[p]] -= g.y_value[p] * a[q];
    lf.backward(t);
    z.resize(r.size());
    for (int k = 0; k < base; ++k) z[lf.perm[k]] = t[k];
    for (int q = 0; q < m; ++q) z[base + q] = a[q] + (g.parent[q] >= 0 ? z[g.parent[q]] : 0.0);
}

}  // namespace xcut
