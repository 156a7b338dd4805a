#include "systems/solver/beside_factor.h"

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

bool factor_beside(const LinearSystem& A, const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask,
                   BesideFactor& f) {
    Eigen::SparseMatrix<double> a;
    copy_to_scalar(A, a, true);
    const int base = static_cast<int>(a.rows()), m = block.rows;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(a.nonZeros() + 2 * block.coupling.size() + block.stiffness.size() + m);
    for (int j = 0; j < a.outerSize(); ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it) entries.emplace_back(it.row(), it.col(), it.value());
    for (const Eigen::Triplet<double>& t : block.coupling) {
        if (mask[t.col()] == 0.0) continue;
        entries.emplace_back(base + t.row(), t.col(), stiff_scale * t.value());
        entries.emplace_back(t.col(), base + t.row(), stiff_scale * t.value());
    }
    Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(m);
    for (const Eigen::Triplet<double>& t : block.stiffness) {
        entries.emplace_back(base + t.row(), base + t.col(), stiff_scale * t.value());
        if (t.row() == t.col()) diagonal[t.row()] += t.value();
    }
    // An amplitude without stiffness (none reaches it) gets 1: nothing couples to it.
    for (int i = 0; i < m; ++i)
        entries.emplace_back(base + i, base + i, diagonal[i] > 0.0 ? stiff_scale * kBesideRegularization * diagonal[i] : 1.0);
    f.matrix.resize(base + m, base + m);
    f.matrix.setFromTriplets(entries.begin(), entries.end());
    with_cholmod_blas([&] { f.llt.compute(f.matrix); });
    f.ok = f.llt.info() == Eigen::Success;
    f.base = base, f.topology = A.topology, f.age = 0, f.last_iterations = 0;
    f.lnz = f.ok ? f.llt.cholmod().lnz : 0.0;
    return f.ok;
}

}  // namespace xcut
