#pragma once
// A Cholesky factor A = P^T L L^T P as the step applies it, without BLAS: views of CHOLMOD's
// supernodal factor (or of any lower triangular matrix stored by columns, each column then a
// supernode of its own). Supernode s holds columns [first, first + cols) of L as a dense
// rows x cols column-major block over its row list (row[0 .. cols) are its own columns, then the
// rows below), as CHOLMOD stores it (Chen, Davis, Hager & Rajamanickam 2008). perm[k] is the row
// of A that is row k of P A P^T.
//
// Why not CHOLMOD's solve: it calls BLAS, and Debian's serial OpenBLAS is not safe to call from
// two threads at once, while the next factor is computed on the background thread with BLAS
// (systems/solver/factor_background.h). The dense blocks are xcut's own kernels
// (systems/kernels/solver/supernode_solve.h: AVX2 where the CPU has it, the same bits without).
// The views are valid while the factor they view lives.
//
// The two triangular solves are split over the team's threads by subtrees of the supernodal
// elimination tree (the subtree-to-thread mapping of Geist & Ng 1989, "Task scheduling for
// parallel sparse Cholesky factorization"; CHOLMOD numbers supernodes in postorder, so a subtree is
// a range of them): each thread solves its subtrees, and one thread the supernodes above them (the
// top separators). Forward, a subtree's updates to rows above it are recorded in order and replayed
// by the top's thread in the supernodes' order, so every entry of x is updated in the order of the
// serial solve: the same bits on any number of threads and as the serial solve itself. Backward,
// the top first, then the subtrees, each reading only what is final.
#include <omp.h>

#include <Eigen/Core>
#include <array>
#include <type_traits>
#include <vector>

#include "systems/solver/cholmod_pages.h"

namespace xcut {

struct LowerFactor {
    struct Supernode {
        int first = 0, cols = 0, rows = 0;
        const int* row = nullptr;       ///< its row list (rows entries)
        const double* value = nullptr;  ///< rows x cols, column-major
        const float* value32 = nullptr; ///< the same rounded to single precision, when the solves use it
    };
    int n = 0;
    const int* perm = nullptr;
    std::vector<Supernode> supernodes;
    std::vector<int> supernode_of;  ///< per column
    int max_rows = 0;               ///< the most rows any supernode has
    /// L's entries rounded to single precision, supernode after supernode (make_single), when the
    /// step's solves read them: half the bytes of a solve, which is bound by memory on a large
    /// factor. Empty: the solves read `value`. See make_single for what it costs in precision. In
    /// the kept blocks (systems/solver/cholmod_pages.h): the next factor's copy reuses its pages.
    KeptArray<float> single;
    bool is_single() const { return !single.empty(); }

    /// The solves' split (see above): bins of subtrees, one bin a thread; 0 bins: all top.
    struct Split {
        int bins = 0;
        std::vector<std::array<int, 2>> range;  ///< subtrees as supernode ranges [lo, hi), lo increasing
        std::vector<int> bin_of;                ///< per range: its bin
        std::vector<int> record_start;          ///< per range (+ 1 at the end): its recorded updates' offset
        std::vector<int> range_of;              ///< per supernode: its range, -1 on top
    } split;
    /// What a team's threads share in a split solve (sized by the solve).
    struct Scratch {
        Eigen::VectorXd t;            ///< the permuted vector being solved (L^-1 P src between the solves)
        std::vector<double> record;   ///< the subtrees' updates to the rows above them, in order
        Eigen::VectorXf t32;          ///< t and record as a single-precision factor's solves keep them
        std::vector<float> record32;
    };
    /// What solve_in_team runs between the solves when there is nothing to run.
    struct NoBetween {
        void operator()() const {}
    };

    int rows() const { return n; }
    /// Column j's first row below the diagonal: j's parent in the elimination tree, -1 at a root.
    int etree_parent(int j) const {
        const Supernode& s = supernodes[supernode_of[j]];
        const int k = j - s.first;
        return k + 1 < s.rows ? s.row[k + 1] : -1;
    }
    /// Columns j to the end of j's supernode of the forward solve L x = b for `width` right-hand
    /// sides stored row by row (x[width i + c]): for each column i in turn, x_i /= L_ii, then x_i
    /// taken off the rows below it. On the supernode's rows gathered into `block` (at least width x
    /// its rows) and scattered back, so that the columns' updates run over contiguous memory: the
    /// operations and their order of a column-by-column elimination on x's scattered rows, and its
    /// bits (1.3x faster on the cut's new columns of the 1 mm skin and the 20k-tet block, whose
    /// reaches end in the large supernodes at the top). Returns the columns done.
    template <int width>
    int eliminate_tail(int j, double* x, double* block) const {
        const Supernode& s = supernodes[supernode_of[j]];
        const int k = j - s.first, len = s.rows - k;
        const int* row = s.row + k;
        for (int p = 0; p < len; ++p)
            for (int c = 0; c < width; ++c) block[width * p + c] = x[width * row[p] + c];
        for (int q = 0; q < s.cols - k; ++q) {  // column k + q: its entries are rows q.. of the block
            const size_t at = static_cast<size_t>(k + q) * s.rows + k + q;
            if (s.value32) eliminate_dense<width>(s.value32 + at, len - q, block + width * q);
            else eliminate_dense<width>(s.value + at, len - q, block + width * q);
        }
        for (int p = 0; p < len; ++p)
            for (int c = 0; c < width; ++c) x[width * row[p] + c] = block[width * p + c];
        return s.cols - k;
    }
    /// z = A^-1 r = P^T L^-T L^-1 P r.
    void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;

    /// The split solve's parts, on sh.t (sh.t32 when single). forward_bin: bin b's subtrees of
    /// L t = P src (their columns of t gathered from src first when src is given), their updates
    /// above them recorded; forward_top: the rest (the top's columns gathered first), replaying
    /// the records. backward_top, backward_bin: L^T t = t for the top, then bin b's subtrees, each
    /// column scattered to dst (dst[perm[k]] = t[k]) when dst is given.
    void forward_bin(int b, const Eigen::VectorXd* src, Scratch& sh) const;
    /// With `whole`, forward_top and backward_top solve every supernode: the serial solve, in the
    /// same order, without records.
    void forward_top(const Eigen::VectorXd* src, Scratch& sh, bool whole = false) const;
    void backward_top(Scratch& sh, Eigen::VectorXd* dst, bool whole = false) const;
    void backward_bin(int b, Scratch& sh, Eigen::VectorXd* dst) const;
    /// Sizes `sh` for a split solve.
    void prepare(Scratch& sh) const;

    /// dst = A^-1 src through sh.t, by every thread of a team (or outside any parallel region:
    /// never inside a single or a loop of one); `between()` runs on one thread between the forward
    /// and the backward solve (t = L^-1 P src then; it may change t); sh prepared, dst sized.
    template <class Between>
    void solve_in_team(const Eigen::VectorXd& src, Eigen::VectorXd& dst, Scratch& sh, Between&& between) const {
        if (omp_get_num_threads() == 1) {  // the serial order without the records: the same bits
            serial_in(src, dst, sh, between);
            return;
        }
        if (split.bins == 0) {  // not split: one thread solves, the team waits once
#pragma omp single
            serial_in(src, dst, sh, between);
            return;
        }
#pragma omp for schedule(static, 1)
        for (int b = 0; b < split.bins; ++b) forward_bin(b, &src, sh);
#pragma omp single
        {
            forward_top(&src, sh);
            between_in_double(sh, between);
            backward_top(sh, &dst);
        }
#pragma omp for schedule(static, 1)
        for (int b = 0; b < split.bins; ++b) backward_bin(b, sh, &dst);
    }

private:
    /// One column of the elimination on rows stored one after the other (y[width p + c]: entry p of
    /// the column, L_jj's first).
    template <int width, class Real>
    static void eliminate_dense(const Real* v, int len, double* y) {
        double xj[width];
        for (int c = 0; c < width; ++c) xj[c] = y[c] /= v[0];
        for (int p = 1; p < len; ++p)
            for (int c = 0; c < width; ++c) y[width * p + c] -= v[p] * xj[c];
    }
    template <class Between>
    void serial_in(const Eigen::VectorXd& src, Eigen::VectorXd& dst, Scratch& sh, Between& between) const {
        forward_top(&src, sh, true);
        between_in_double(sh, between);
        backward_top(sh, &dst, true);
    }
    /// between() on sh.t in double precision: a single-precision solve's vector copied there and back.
    template <class Between>
    void between_in_double(Scratch& sh, Between& between) const {
        if constexpr (!std::is_same_v<std::decay_t<Between>, NoBetween>) {
            if (!is_single()) return between();
            sh.t = sh.t32.cast<double>();
            between();
            sh.t32 = sh.t.cast<float>();
        }
    }
};

/// Splits the solves of `f` into `bins` bins of subtrees whose work (the flops of their
/// supernodes) is within 10 % of each other where the tree allows, if L has at least
/// `min_nonzeros` entries (else none: the team's barriers would cost more than they save).
void split_solves(LowerFactor& f, int bins, double min_nonzeros);

/// Views of a lower triangular matrix stored by columns: column j's entries [outer[j],
/// outer[j] + count[j]) (count null: up to outer[j + 1]), its diagonal first, rows increasing.
/// False if a column is not so.
bool view_columns(int n, const int* outer, const int* count, const int* inner, const double* value, const int* perm,
                  LowerFactor& out);
/// Rounds f's entries to single precision for its solves (LowerFactor::single). The solves then
/// run in single precision too (the vector and the records; src and dst stay double): a solve's
/// relative error grows from about 1e-16 to about 1e-7 times the condition of L, which CG meets as
/// a slightly different preconditioner. What it preconditions, and the residual CG checks against
/// its tolerance, stay double: the solution's tolerance is unchanged. Mixed-precision
/// preconditioning of this kind: Arioli & Duff 2009 ("Using FGMRES to obtain backward stability in
/// mixed precision"), Abdelfattah et al. 2021 ("A survey of numerical linear algebra methods
/// utilizing mixed-precision arithmetic"). The sparse column solves (eliminate_tail) read the
/// rounded entries in double arithmetic.
void make_single(LowerFactor& f);
/// Views of a supernodal factor given as CHOLMOD stores it (super, pi, px: nsuper + 1 each).
void view_supernodes(int n, int nsuper, const int* super, const int* pi, const int* px, const int* s,
                     const double* x, const int* perm, LowerFactor& out);

}  // namespace xcut
