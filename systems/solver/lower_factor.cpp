#include "systems/solver/lower_factor.h"

namespace xcut {
namespace {

using Block = Eigen::Map<const Eigen::MatrixXd>;

void index_columns(LowerFactor& out) {
    out.supernode_of.assign(out.n, 0);
    for (int s = 0; s < static_cast<int>(out.supernodes.size()); ++s)
        for (int k = 0; k < out.supernodes[s].cols; ++k) out.supernode_of[out.supernodes[s].first + k] = s;
}

}  // namespace

void LowerFactor::forward(Eigen::VectorXd& x) const {
    Eigen::VectorXd below;
    for (const Supernode& s : supernodes) {
        const Block L(s.value, s.rows, s.cols);
        auto xs = x.segment(s.first, s.cols);
        L.topRows(s.cols).triangularView<Eigen::Lower>().solveInPlace(xs);
        if (s.rows == s.cols) continue;
        below.noalias() = L.bottomRows(s.rows - s.cols) * xs;
        for (int i = 0; i < s.rows - s.cols; ++i) x[s.row[s.cols + i]] -= below[i];
    }
}

void LowerFactor::backward(Eigen::VectorXd& x) const {
    Eigen::VectorXd below;
    for (auto it = supernodes.rbegin(); it != supernodes.rend(); ++it) {
        const Supernode& s = *it;
        const Block L(s.value, s.rows, s.cols);
        auto xs = x.segment(s.first, s.cols);
        if (s.rows > s.cols) {
            below.resize(s.rows - s.cols);
            for (int i = 0; i < s.rows - s.cols; ++i) below[i] = x[s.row[s.cols + i]];
            xs.noalias() -= L.bottomRows(s.rows - s.cols).transpose() * below;
        }
        L.topRows(s.cols).triangularView<Eigen::Lower>().transpose().solveInPlace(xs);
    }
}

void LowerFactor::solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    Eigen::VectorXd t(n);
    for (int k = 0; k < n; ++k) t[k] = r[perm[k]];
    forward(t);
    backward(t);
    z.resize(n);
    for (int k = 0; k < n; ++k) z[perm[k]] = t[k];
}

bool view_columns(int n, const int* outer, const int* count, const int* inner, const double* value, const int* perm,
                  LowerFactor& out) {
    out.n = n, out.perm = perm;
    out.supernodes.clear();
    for (int j = 0; j < n; ++j) {
        const int begin = outer[j], end = count ? begin + count[j] : outer[j + 1];
        if (end <= begin || inner[begin] != j) return false;
        for (int p = begin + 1; p < end; ++p)
            if (inner[p] <= inner[p - 1]) return false;
        out.supernodes.push_back({j, 1, end - begin, inner + begin, value + begin});
    }
    index_columns(out);
    return true;
}

void view_supernodes(int n, int nsuper, const int* super, const int* pi, const int* px, const int* s,
                     const double* x, const int* perm, LowerFactor& out) {
    out.n = n, out.perm = perm;
    out.supernodes.clear();
    for (int k = 0; k < nsuper; ++k)
        out.supernodes.push_back({super[k], super[k + 1] - super[k], pi[k + 1] - pi[k], s + pi[k], x + px[k]});
    index_columns(out);
}

}  // namespace xcut
