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
// (systems/solver/factor_background.h). The dense blocks here are Eigen's own kernels; on the
// default skin and hand_dorsum factors a solve takes about what CHOLMOD's supernodal one takes.
// The views are valid while the factor they view lives.
#include <Eigen/Core>
#include <vector>

namespace xcut {

struct LowerFactor {
    struct Supernode {
        int first = 0, cols = 0, rows = 0;
        const int* row = nullptr;       ///< its row list (rows entries)
        const double* value = nullptr;  ///< rows x cols, column-major
    };
    int n = 0;
    const int* perm = nullptr;
    std::vector<Supernode> supernodes;
    std::vector<int> supernode_of;  ///< per column

    int rows() const { return n; }
    /// Column j's first row below the diagonal: j's parent in the elimination tree, -1 at a root.
    int etree_parent(int j) const {
        const Supernode& s = supernodes[supernode_of[j]];
        const int k = j - s.first;
        return k + 1 < s.rows ? s.row[k + 1] : -1;
    }
    /// Column j of the forward solve L x = b for `width` right-hand sides stored row by row
    /// (x[width i + c]): x_j /= L_jj, then x_j taken off the rows below it.
    template <int width>
    void eliminate_column(int j, double* x) const {
        const Supernode& s = supernodes[supernode_of[j]];
        const int k = j - s.first, len = s.rows - k;
        const int* row = s.row + k;
        const double* v = s.value + static_cast<size_t>(k) * s.rows + k;
        double xj[width];
        for (int c = 0; c < width; ++c) xj[c] = x[width * j + c] /= v[0];
        for (int p = 1; p < len; ++p)
            for (int c = 0; c < width; ++c) x[width * row[p] + c] -= v[p] * xj[c];
    }
    /// Solves L x = b in place (x holds b).
    void forward(Eigen::VectorXd& x) const;
    /// Solves L^T x = b in place.
    void backward(Eigen::VectorXd& x) const;
    /// z = A^-1 r = P^T L^-T L^-1 P r.
    void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;
};

/// Views of a lower triangular matrix stored by columns: column j's entries [outer[j],
/// outer[j] + count[j]) (count null: up to outer[j + 1]), its diagonal first, rows increasing.
/// False if a column is not so.
bool view_columns(int n, const int* outer, const int* count, const int* inner, const double* value, const int* perm,
                  LowerFactor& out);
/// Views of a supernodal factor given as CHOLMOD stores it (super, pi, px: nsuper + 1 each).
void view_supernodes(int n, int nsuper, const int* super, const int* pi, const int* px, const int* s,
                     const double* x, const int* perm, LowerFactor& out);

}  // namespace xcut
