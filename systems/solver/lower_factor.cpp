#include "systems/solver/lower_factor.h"

#include <algorithm>
#include <numeric>

#include "systems/kernels/solver/supernode_solve.h"

namespace xcut {
namespace {

template <class Real>
using Vector = Eigen::Matrix<Real, Eigen::Dynamic, 1>;

template <class Real>
const Real* entries(const LowerFactor::Supernode& s);
template <>
const double* entries<double>(const LowerFactor::Supernode& s) { return s.value; }
template <>
const float* entries<float>(const LowerFactor::Supernode& s) { return s.value32; }

void index_columns(LowerFactor& out) {
    // The solves' kernels are taken once, where a factor is first viewed (the load, on the calling
    // thread): a bad XCUT_KERNELS stops the run there with its message, not inside a team's solve.
    supernode_kernels<double>(), supernode_kernels<float>();
    out.supernode_of.assign(out.n, 0);
    out.max_rows = 0;
    for (int s = 0; s < static_cast<int>(out.supernodes.size()); ++s) {
        const LowerFactor::Supernode& sn = out.supernodes[s];
        for (int k = 0; k < sn.cols; ++k) out.supernode_of[sn.first + k] = s;
        out.max_rows = std::max(out.max_rows, sn.rows);
    }
    split_solves(out, 0, 0.0);
}

/// The first column of supernode a, and the end of the columns of supernode range [.., b).
int first_column(const LowerFactor& f, int a) { return f.supernodes[a].first; }
int end_column(const LowerFactor& f, int b) { return f.supernodes[b - 1].first + f.supernodes[b - 1].cols; }

/// Supernode s of the forward solve on x (systems/kernels/solver/supernode_solve.h): its columns
/// solved, and the updates to add to the rows below it, -L21 x_s, returned (in `buffer`, at least
/// s.rows long).
template <class Real>
const Real* eliminate(const LowerFactor::Supernode& s, Vector<Real>& x, Vector<Real>& buffer) {
    Real* w = buffer.data();
    std::copy_n(x.data() + s.first, s.cols, w);
    std::fill(w + s.cols, w + s.rows, Real(0));
    supernode_kernels<Real>().forward(entries<Real>(s), s.rows, s.cols, w);
    std::copy_n(w, s.cols, x.data() + s.first);
    return w + s.cols;
}

/// Supernode s of the backward solve, its columns scattered to dst if given.
template <class Real>
void back_substitute(const LowerFactor::Supernode& s, const int* perm, Vector<Real>& x, Vector<Real>& buffer,
                     Eigen::VectorXd* dst) {
    Real* w = buffer.data();
    std::copy_n(x.data() + s.first, s.cols, w);
    for (int i = s.cols; i < s.rows; ++i) w[i] = x[s.row[i]];
    supernode_kernels<Real>().backward(entries<Real>(s), s.rows, s.cols, w);
    std::copy_n(w, s.cols, x.data() + s.first);
    if (dst)
        for (int k = s.first; k < s.first + s.cols; ++k) (*dst)[perm[k]] = x[k];
}

template <class Real>
void gather(const LowerFactor& f, const Eigen::VectorXd* src, int lo, int hi, Vector<Real>& t) {
    if (src)
        for (int k = lo; k < hi; ++k) t[k] = static_cast<Real>((*src)[f.perm[k]]);
}

template <class Real>
void forward_bin_of(const LowerFactor& f, int b, const Eigen::VectorXd* src, Vector<Real>& t, Real* record) {
    Vector<Real> buffer(f.max_rows);
    const LowerFactor::Split& split = f.split;
    for (size_t k = 0; k < split.range.size(); ++k) {
        if (split.bin_of[k] != b) continue;
        const auto [lo, hi] = split.range[k];
        const int top = end_column(f, hi);  // rows from here on are above the subtree
        gather(f, src, first_column(f, lo), top, t);
        Real* rec = record + split.record_start[k];
        for (int s = lo; s < hi; ++s) {
            const LowerFactor::Supernode& sn = f.supernodes[s];
            const Real* update = eliminate(sn, t, buffer);
            for (int i = 0; i < sn.rows - sn.cols; ++i) {
                const int row = sn.row[sn.cols + i];
                if (row < top) t[row] += update[i];
                else *rec++ = update[i];
            }
        }
    }
}

template <class Real>
void forward_top_of(const LowerFactor& f, const Eigen::VectorXd* src, Vector<Real>& t, const Real* record, bool whole) {
    const int count = static_cast<int>(f.supernodes.size());
    const LowerFactor::Split& split = f.split;
    if (whole) {
        gather(f, src, 0, f.n, t);
    } else {
        for (int s = 0; s < count; ++s)
            if (split.range_of[s] < 0) gather(f, src, f.supernodes[s].first, f.supernodes[s].first + f.supernodes[s].cols, t);
    }
    Vector<Real> buffer(f.max_rows);
    for (int s = 0; s < count; ++s) {
        const int k = whole ? -1 : split.range_of[s];
        if (k >= 0) {  // a subtree: its updates above it, in the order it made them
            const auto [lo, hi] = split.range[k];
            const int top = end_column(f, hi);
            const Real* rec = record + split.record_start[k];
            for (int q = lo; q < hi; ++q) {
                const LowerFactor::Supernode& sn = f.supernodes[q];
                for (int i = sn.cols; i < sn.rows; ++i)
                    if (sn.row[i] >= top) t[sn.row[i]] += *rec++;
            }
            s = hi - 1;
            continue;
        }
        const LowerFactor::Supernode& sn = f.supernodes[s];
        const Real* update = eliminate(sn, t, buffer);
        for (int i = 0; i < sn.rows - sn.cols; ++i) t[sn.row[sn.cols + i]] += update[i];
    }
}

template <class Real>
void backward_top_of(const LowerFactor& f, Vector<Real>& t, Eigen::VectorXd* dst, bool whole) {
    Vector<Real> buffer(f.max_rows);
    for (int s = static_cast<int>(f.supernodes.size()) - 1; s >= 0; --s)
        if (whole || f.split.range_of[s] < 0) back_substitute(f.supernodes[s], f.perm, t, buffer, dst);
}

template <class Real>
void backward_bin_of(const LowerFactor& f, int b, Vector<Real>& t, Eigen::VectorXd* dst) {
    Vector<Real> buffer(f.max_rows);
    const LowerFactor::Split& split = f.split;
    for (int k = static_cast<int>(split.range.size()) - 1; k >= 0; --k) {
        if (split.bin_of[k] != b) continue;
        for (int s = split.range[k][1] - 1; s >= split.range[k][0]; --s) back_substitute(f.supernodes[s], f.perm, t, buffer, dst);
    }
}

}  // namespace

void LowerFactor::forward_bin(int b, const Eigen::VectorXd* src, Scratch& sh) const {
    if (is_single()) forward_bin_of(*this, b, src, sh.t32, sh.record32.data());
    else forward_bin_of(*this, b, src, sh.t, sh.record.data());
}

void LowerFactor::forward_top(const Eigen::VectorXd* src, Scratch& sh, bool whole) const {
    if (is_single()) forward_top_of(*this, src, sh.t32, sh.record32.data(), whole);
    else forward_top_of(*this, src, sh.t, sh.record.data(), whole);
}

void LowerFactor::backward_top(Scratch& sh, Eigen::VectorXd* dst, bool whole) const {
    if (is_single()) backward_top_of(*this, sh.t32, dst, whole);
    else backward_top_of(*this, sh.t, dst, whole);
}

void LowerFactor::backward_bin(int b, Scratch& sh, Eigen::VectorXd* dst) const {
    if (is_single()) backward_bin_of(*this, b, sh.t32, dst);
    else backward_bin_of(*this, b, sh.t, dst);
}

void LowerFactor::prepare(Scratch& sh) const {
    const size_t records = split.record_start.empty() ? 0 : split.record_start.back();
    sh.t.resize(n);
    if (is_single()) sh.t32.resize(n), sh.record32.resize(records);
    else sh.record.resize(records);
}

void LowerFactor::solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    Scratch sh;
    prepare(sh);
    z.resize(n);
    forward_top(&r, sh, true);
    backward_top(sh, &z, true);
}

void make_single(LowerFactor& f) {
    size_t total = 0;
    for (const LowerFactor::Supernode& s : f.supernodes) total += static_cast<size_t>(s.rows) * s.cols;
    f.single.resize(total);
    size_t at = 0;
    for (LowerFactor::Supernode& s : f.supernodes) {
        const size_t size = static_cast<size_t>(s.rows) * s.cols;
        for (size_t k = 0; k < size; ++k) f.single[at + k] = static_cast<float>(s.value[k]);
        s.value32 = f.single.data() + at;
        at += size;
    }
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
