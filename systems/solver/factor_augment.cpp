#include "systems/solver/factor_augment.h"

#include <algorithm>
#include <vector>

#include "engine/parallel.h"

namespace xcut {
namespace {

/// Solves for the three columns of Y of new node `node` (its axes) into `out`, and fills their
/// columns of C (rows: every new DOF). B's columns come from the node's own block row (A is
/// symmetric: A(i, node) = A(node, i)^T): B = A'_12 + E^T A'_22, C = A'_22 (jump basis). One sparse
/// solve for the three axes; it depends on the node alone (the bits whichever thread solves it).
/// (Passes of 2 and 4 nodes side by side, their reaches read once: no faster on the 20k-tet block.)
void solve_columns(const LinearSystem& A, int node, const FactorAugment& g, SparseForward<3>& solver,
                   Eigen::Ref<Eigen::MatrixXd> C, SparseColumns& out) {
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
    take_columns(solver, 3, out);
    solver.clear();
}

/// Columns of Y a factor's augmented block is given room for at once: past the 120 new DOFs at
/// which a successor factor is asked for (systems/solver/linear_solver.cpp), with the split steps
/// until it is taken. Y grown by doubling moved all its columns into fresh pages at each growth
/// (3-8 ms of a split step on the 20k-tet block, Y at 2.5 MB); with room made once, at the mean
/// entries per column of the first split, a split touches only its own columns' pages (and a
/// successor factor takes them over: hand_on_columns).
constexpr int kAugmentColumnsRoom = 256;

void reserve_columns(const std::vector<SparseColumns>& solved, FactorAugment& g) {
    size_t entries = g.y_row.size(), columns = g.y_start.size() - 1;
    for (const SparseColumns& node : solved) entries += node.row.size(), columns += node.end.size();
    if (entries <= g.y_row.capacity() || columns == 0) return;
    const size_t room = std::max(2 * entries, entries / columns * kAugmentColumnsRoom);
    g.y_row.reserve(room), g.y_value.reserve(room);
    g.y_start.reserve(std::max<size_t>(2 * columns, kAugmentColumnsRoom) + 1);
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
    // The new nodes' solves on the threads (each its own work vectors), appended in node order.
    const int nodes = (m - kept) / 3;
    std::vector<SparseColumns> solved(nodes);
    parallel_for_uneven_scratch(nodes, [&] { return SparseForward<3>(lf); }, [&](int n, SparseForward<3>& solver) {
        solve_columns(A, base / 3 + kept / 3 + n, g, solver, C.middleCols(3 * n, 3), solved[n]);
    });
    reserve_columns(solved, g);
    for (const SparseColumns& node : solved) append_columns(node, g.y_start, g.y_row, g.y_value);
    // S's rows and columns of the new DOFs, C - Y^T Y: column k's entries up to its diagonal (and
    // their mirrors) are k's alone, on the threads.
    g.S.conservativeResize(m, m);
    parallel_for_uneven_scratch(m - kept, [&] { return Eigen::VectorXd(Eigen::VectorXd::Zero(base)); }, [&](int i, Eigen::VectorXd& w) {
        const int k = kept + i;
        for (int p = g.y_start[k]; p < g.y_start[k + 1]; ++p) w[g.y_row[p]] = g.y_value[p];
        for (int q = 0; q <= k; ++q) g.S(q, k) = g.S(k, q) = C(q, k - kept) - g.column_dot(q, w);
        for (int p = g.y_start[k]; p < g.y_start[k + 1]; ++p) w[g.y_row[p]] = 0.0;
    });
    if (m == 0) return g.ok = true;  // a split among existing phantoms: the old factor alone
    g.schur.compute(g.S);
    return g.ok = g.schur.info() == Eigen::Success;
}

}  // namespace xcut
