#include "systems/solver/lower_factor.h"

#include <algorithm>
#include <numeric>

namespace xcut {
namespace {

using Block = Eigen::Map<const Eigen::MatrixXd>;

void index_columns(LowerFactor& out) {
    out.supernode_of.assign(out.n, 0);
    out.max_below = 0;
    for (int s = 0; s < static_cast<int>(out.supernodes.size()); ++s) {
        const LowerFactor::Supernode& sn = out.supernodes[s];
        for (int k = 0; k < sn.cols; ++k) out.supernode_of[sn.first + k] = s;
        out.max_below = std::max(out.max_below, sn.rows - sn.cols);
    }
    split_solves(out, 0, 0.0);
}

/// The first column of supernode a, and the end of the columns of supernode range [.., b).
int first_column(const LowerFactor& f, int a) { return f.supernodes[a].first; }
int end_column(const LowerFactor& f, int b) { return f.supernodes[b - 1].first + f.supernodes[b - 1].cols; }

/// Supernode s of the forward solve: its columns solved, below = L21 x_s.
Eigen::Map<Eigen::VectorXd> eliminate(const LowerFactor::Supernode& s, Eigen::VectorXd& x, Eigen::VectorXd& buffer) {
    const Block L(s.value, s.rows, s.cols);
    auto xs = x.segment(s.first, s.cols);
    L.topRows(s.cols).triangularView<Eigen::Lower>().solveInPlace(xs);
    Eigen::Map<Eigen::VectorXd> below(buffer.data(), s.rows - s.cols);
    if (s.rows > s.cols) below.noalias() = L.bottomRows(s.rows - s.cols) * xs;
    return below;
}

/// Supernode s of the backward solve, its columns scattered to dst if given.
void back_substitute(const LowerFactor::Supernode& s, const int* perm, Eigen::VectorXd& x, Eigen::VectorXd& buffer,
                     Eigen::VectorXd* dst) {
    const Block L(s.value, s.rows, s.cols);
    auto xs = x.segment(s.first, s.cols);
    if (s.rows > s.cols) {
        Eigen::Map<Eigen::VectorXd> below(buffer.data(), s.rows - s.cols);
        for (int i = 0; i < s.rows - s.cols; ++i) below[i] = x[s.row[s.cols + i]];
        xs.noalias() -= L.bottomRows(s.rows - s.cols).transpose() * below;
    }
    L.topRows(s.cols).triangularView<Eigen::Lower>().transpose().solveInPlace(xs);
    if (dst)
        for (int k = s.first; k < s.first + s.cols; ++k) (*dst)[perm[k]] = x[k];
}

void gather(const LowerFactor& f, const Eigen::VectorXd* src, int lo, int hi, Eigen::VectorXd& t) {
    if (src)
        for (int k = lo; k < hi; ++k) t[k] = (*src)[f.perm[k]];
}

}  // namespace

void LowerFactor::forward_bin(int b, const Eigen::VectorXd* src, Eigen::VectorXd& t, double* record) const {
    Eigen::VectorXd buffer(max_below);
    for (size_t k = 0; k < split.range.size(); ++k) {
        if (split.bin_of[k] != b) continue;
        const auto [lo, hi] = split.range[k];
        const int top = end_column(*this, hi);  // rows from here on are above the subtree
        gather(*this, src, first_column(*this, lo), top, t);
        double* rec = record + split.record_start[k];
        for (int s = lo; s < hi; ++s) {
            const Supernode& sn = supernodes[s];
            const auto below = eliminate(sn, t, buffer);
            for (int i = 0; i < sn.rows - sn.cols; ++i) {
                const int row = sn.row[sn.cols + i];
                if (row < top) t[row] -= below[i];
                else *rec++ = below[i];
            }
        }
    }
}

void LowerFactor::forward_top(const Eigen::VectorXd* src, Eigen::VectorXd& t, const double* record, bool whole) const {
    const int count = static_cast<int>(supernodes.size());
    if (whole) {
        gather(*this, src, 0, n, t);
    } else {
        for (int s = 0; s < count; ++s)
            if (split.range_of[s] < 0) gather(*this, src, supernodes[s].first, supernodes[s].first + supernodes[s].cols, t);
    }
    Eigen::VectorXd buffer(max_below);
    for (int s = 0; s < count; ++s) {
        const int k = whole ? -1 : split.range_of[s];
        if (k >= 0) {  // a subtree: its updates above it, in the order it made them
            const auto [lo, hi] = split.range[k];
            const int top = end_column(*this, hi);
            const double* rec = record + split.record_start[k];
            for (int q = lo; q < hi; ++q) {
                const Supernode& sn = supernodes[q];
                for (int i = sn.cols; i < sn.rows; ++i)
                    if (sn.row[i] >= top) t[sn.row[i]] -= *rec++;
            }
            s = hi - 1;
            continue;
        }
        const Supernode& sn = supernodes[s];
        const auto below = eliminate(sn, t, buffer);
        for (int i = 0; i < sn.rows - sn.cols; ++i) t[sn.row[sn.cols + i]] -= below[i];
    }
}

void LowerFactor::backward_top(Eigen::VectorXd& t, Eigen::VectorXd* dst, bool whole) const {
    Eigen::VectorXd buffer(max_below);
    for (int s = static_cast<int>(supernodes.size()) - 1; s >= 0; --s)
        if (whole || split.range_of[s] < 0) back_substitute(supernodes[s], perm, t, buffer, dst);
}

void LowerFactor::backward_bin(int b, Eigen::VectorXd& t, Eigen::VectorXd* dst) const {
    Eigen::VectorXd buffer(max_below);
    for (int k = static_cast<int>(split.range.size()) - 1; k >= 0; --k) {
        if (split.bin_of[k] != b) continue;
        for (int s = split.range[k][1] - 1; s >= split.range[k][0]; --s) back_substitute(supernodes[s], perm, t, buffer, dst);
    }
}

void LowerFactor::prepare(Scratch& sh) const {
    sh.t.resize(n);
    sh.record.resize(split.record_start.empty() ? 0 : split.record_start.back());
}

void LowerFactor::forward(Eigen::VectorXd& x) const { forward_top(nullptr, x, nullptr, true); }

void LowerFactor::backward(Eigen::VectorXd& x) const { backward_top(x, nullptr, true); }

void LowerFactor::solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    Eigen::VectorXd t(n);
    z.resize(n);
    forward_top(&r, t, nullptr, true);
    backward_top(t, &z, true);
}

void split_solves(LowerFactor& f, int bins, double min_nonzeros) {
    LowerFactor::Split& out = f.split;
    const int count = static_cast<int>(f.supernodes.size());
    out = LowerFactor::Split{};
    out.range_of.assign(count, -1);
    out.record_start.assign(1, 0);
    double nonzeros = 0.0;
    for (const LowerFactor::Supernode& s : f.supernodes) nonzeros += double(s.rows) * s.cols;
    if (bins < 2 || nonzeros < min_nonzeros) return;
    // The supernodal tree: parents, subtree work and first supernode (postorder: a subtree is
    // [first, s]; a tree numbered otherwise is not split).
    std::vector<int> parent(count, -1), first(count), size(count, 1);
    std::vector<double> work(count);
    std::iota(first.begin(), first.end(), 0);
    for (int s = 0; s < count; ++s) {
        const LowerFactor::Supernode& sn = f.supernodes[s];
        work[s] += double(sn.rows) * sn.cols;
        if (sn.rows == sn.cols) continue;
        const int p = f.supernode_of[sn.row[sn.cols]];
        if (p <= s) return;
        parent[s] = p, work[p] += work[s], size[p] += size[s], first[p] = std::min(first[p], first[s]);
    }
    for (int s = 0; s < count; ++s)
        if (s - first[s] + 1 != size[s]) return;
    std::vector<std::vector<int>> children(count);
    std::vector<int> list;
    for (int s = 0; s < count; ++s) (parent[s] < 0 ? list : children[parent[s]]).push_back(s);
    // Geist & Ng: the heaviest subtree is replaced by its children (it goes on top) until the
    // subtrees, dealt heaviest first to the lightest bin, fill the bins within 10 % of each other.
    std::vector<double> load;
    std::vector<int> bin_of_root;
    for (int round = 0; round < 256; ++round) {
        std::sort(list.begin(), list.end(), [&](int a, int b) { return work[a] != work[b] ? work[a] > work[b] : a < b; });
        load.assign(bins, 0.0);
        bin_of_root.assign(list.size(), 0);
        for (size_t i = 0; i < list.size(); ++i) {
            const int lightest = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
            load[lightest] += work[list[i]], bin_of_root[i] = lightest;
        }
        const double most = *std::max_element(load.begin(), load.end()), least = *std::min_element(load.begin(), load.end());
        if (most <= 1.1 * least || children[list[0]].empty()) break;
        const int heaviest = list[0];
        list.erase(list.begin());
        list.insert(list.end(), children[heaviest].begin(), children[heaviest].end());
    }
    std::vector<int> order(list.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return list[a] < list[b]; });
    out.bins = bins;
    for (int i : order) {
        const int root = list[i], lo = first[root], hi = root + 1, top = end_column(f, hi);
        int records = 0;
        for (int s = lo; s < hi; ++s) {
            out.range_of[s] = static_cast<int>(out.range.size());
            const LowerFactor::Supernode& sn = f.supernodes[s];
            for (int r = sn.cols; r < sn.rows; ++r) records += sn.row[r] >= top;
        }
        out.range.push_back({lo, hi});
        out.bin_of.push_back(bin_of_root[i]);
        out.record_start.push_back(out.record_start.back() + records);
    }
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
