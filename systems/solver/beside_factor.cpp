#include "systems/solver/beside_factor.h"

#include <algorithm>
#include <vector>

#include "systems/kernels/solver/block_sparse.h"
#include "systems/solver/cholesky_factor.h"

namespace xcut {

void BesideFactor::solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    Eigen::VectorXd padded = Eigen::VectorXd::Zero(matrix.rows());
    padded.head(base) = r;
    Eigen::VectorXd full;
    with_cholmod_blas([&] { full = llt.solve(padded); });
    z = full.head(base);
}

namespace {

/// An entry of M below A: (column, row, value).
struct Entry {
    int column, row;
    double value;
};

/// Sorts by (column, row), keeping the given order among equal keys, and sums those in that order
/// (as setFromTriplets does).
void sort_and_sum(std::vector<Entry>& e) {
    std::stable_sort(e.begin(), e.end(), [](const Entry& a, const Entry& b) {
        return a.column != b.column ? a.column < b.column : a.row < b.row;
    });
    size_t out = 0;
    for (size_t k = 0; k < e.size(); ++k) {
        if (out > 0 && e[out - 1].column == e[k].column && e[out - 1].row == e[k].row) e[out - 1].value += e[k].value;
        else e[out++] = e[k];
    }
    e.resize(out);
}

}  // namespace

bool factor_beside(const LinearSystem& A, const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask,
                   BesideFactor& f) {
    const int n = A.rows(), base = 3 * n, m = block.rows;
    // Below A's rows: s C in A's columns (held axes dropped), then s (H + eps D_H) in its own.
    std::vector<Entry> below;
    below.reserve(block.coupling.size() + block.stiffness.size() / 2 + m);
    for (const Eigen::Triplet<double>& t : block.coupling)
        if (mask[t.col()] != 0.0) below.push_back({t.col(), base + t.row(), stiff_scale * t.value()});
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(m);
    for (const Eigen::Triplet<double>& t : block.stiffness) {
        if (t.row() >= t.col()) below.push_back({base + t.col(), base + t.row(), stiff_scale * t.value()});
        if (t.row() == t.col()) diagonal[t.row()] += t.value();
    }
    // An amplitude without stiffness (none reaches it) gets 1: nothing couples to it.
    for (int i = 0; i < m; ++i)
        below.push_back({base + i, base + i, diagonal[i] > 0.0 ? stiff_scale * kBesideRegularization * diagonal[i] : 1.0});
    sort_and_sum(below);
    // M's lower triangle by columns, which is all CHOLMOD reads (the factor's Lower view): column r
    // of A's part is A's row r from its diagonal on (A is symmetric; A's own factor reads it so too).
    std::vector<int> outer(base + m + 1, 0);
    for (int i = 0; i < n; ++i)
        for (int r = 0; r < 3; ++r)
            for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
                outer[3 * i + r + 1] += std::max(0, std::min(3, 3 * A.column[b] + 3 - (3 * i + r)));
    for (const Entry& e : below) ++outer[e.column + 1];
    for (int c = 0; c < base + m; ++c) outer[c + 1] += outer[c];
    f.matrix.resize(base + m, base + m);
    f.matrix.resizeNonZeros(outer.back());
    std::copy(outer.begin(), outer.end(), f.matrix.outerIndexPtr());
    int* inner = f.matrix.innerIndexPtr();
    double* value = f.matrix.valuePtr();
    std::vector<int> at(outer.begin(), outer.end() - 1);
    for (int i = 0; i < n; ++i)
        for (int r = 0; r < 3; ++r)
            for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
                for (int c = 0; c < 3; ++c)
                    if (3 * A.column[b] + c >= 3 * i + r)
                        inner[at[3 * i + r]] = 3 * A.column[b] + c, value[at[3 * i + r]++] = A.value[9 * b + 3 * r + c];
    for (const Entry& e : below) inner[at[e.column]] = e.row, value[at[e.column]++] = e.value;
    with_cholmod_blas([&] { f.llt.compute(f.matrix); });
    f.ok = f.llt.info() == Eigen::Success;
    f.base = base, f.topology = A.topology, f.age = 0, f.last_iterations = 0;
    f.lnz = f.ok ? f.llt.cholmod().lnz : 0.0;
    return f.ok;
}

}  // namespace xcut
