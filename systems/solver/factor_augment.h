#pragma once
// The old Cholesky factor solving the grown system of a cut, through an augmented block (after
// Yeung, Crouch & Pothen 2016, "Interactively cutting and constraining vertices in meshes using
// augmented matrices": the factor in use keeps solving, the new DOFs are handled by a small Schur
// complement, and a fresh factor is computed off the step).
//
// A split adds phantom nodes (the other side's vertices, components/cut_elements.h) after the
// nodes the factor was computed for. In the jump basis x_new = E x_old + a (a: each phantom's jump
// from its mesh node, the shifted-Heaviside DOF of the paper's eq. 1), the grown matrix A' becomes
//   T^T A' T = [[A11, B], [B^T, C]],  B = A'_12 + E^T A'_22,  C = A'_22,
// and A11 is the stiffness of the old DOFs with every jump zero: the two virtual elements of a
// split element then sum to the whole element (their weights V_s/V sum to 1), so A11 is the matrix
// the old factor was computed for, up to the rotations' drift since. The preconditioner is the
// exact inverse of [[L L^T, B], [B^T, C]] by block elimination:
//   Y = L^-1 P B (sparse: B's columns touch a few rows, their solves only the rows those reach),
//   S = C - Y^T Y (dense, one row per new DOF), factored by Cholesky,
//   forward  v = L^-1 P g1,  a = S^-1 (g2 - Y^T v),  backward  u = P^T L^-T (v - Y a),
// with g = T^T r before and z = T (u, a) after. Per application: one solve with the old factor
// plus two products with Y and one with S^-1. Extended at each new pattern for the DOFs new since:
// their columns of Y (one reach per node for its three axes) and their rows of S.
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "components/linear_system.h"
#include "systems/solver/lower_factor.h"

namespace xcut {

/// x = L^-1 P b for a right-hand side b with few entries (`width` of them side by side, stored row
/// by row), visiting only the rows their solves reach up the elimination tree (Gilbert & Peierls
/// 1988: the pattern of L's column j lies on j's path): add b's entries, solve, read x over reach(),
/// clear.
template <int width>
class SparseForward {
public:
    explicit SparseForward(const LowerFactor& lf)
        : lf_(lf), where_(lf.rows()), x_(width * lf.rows(), 0.0), marked_(lf.rows(), 0), block_(width * lf.max_rows) {
        for (int k = 0; k < lf.rows(); ++k) where_[lf.perm[k]] = k;
    }
    /// b's entries on row `row` of A: v[c] for each of its `width` sides.
    void add(int row, const double* v) {
        const int at = where_[row];
        for (int c = 0; c < width; ++c) x_[width * at + c] += v[c];
        for (int j = at; j != -1 && !marked_[j]; j = lf_.etree_parent(j)) marked_[j] = 1, reach_.push_back(j);
    }
    /// The reach in increasing order (a child before its parent: a topological order) holds the
    /// rest of each supernode it enters (the etree runs up a supernode's columns one by one): the
    /// supernodes' tails, each eliminated as a block.
    void solve() {
        std::sort(reach_.begin(), reach_.end());
        for (size_t i = 0; i < reach_.size();) i += lf_.eliminate_tail<width>(reach_[i], x_.data(), block_.data());
    }
    /// The rows of P A P^T the solve reached, increasing, and x there (x(j)[c]).
    const std::vector<int>& reach() const { return reach_; }
    const double* x(int j) const { return x_.data() + width * j; }
    void clear() {
        for (int j : reach_) {
            for (int c = 0; c < width; ++c) x_[width * j + c] = 0.0;
            marked_[j] = 0;
        }
        reach_.clear();
    }

private:
    const LowerFactor& lf_;
    std::vector<int> where_;  ///< row of A -> row of P A P^T
    std::vector<double> x_;
    std::vector<char> marked_;
    std::vector<int> reach_;
    std::vector<double> block_;  ///< a supernode's rows, gathered (eliminate_tail)
};

/// Columns of sparse solves kept by their entries: rows, values, and where each column ends.
struct SparseColumns {
    std::vector<int> row, end;
    std::vector<double> value;
};

/// Appends the solver's first `count` columns (their entries off zero, rows increasing) to out.
template <int width>
void take_columns(const SparseForward<width>& solver, int count, SparseColumns& out) {
    for (int c = 0; c < count; ++c) {
        for (int j : solver.reach())
            if (solver.x(j)[c] != 0.0) out.row.push_back(j), out.value.push_back(solver.x(j)[c]);
        out.end.push_back(static_cast<int>(out.row.size()));
    }
}

/// Appends part's columns to a matrix stored by sparse columns (start, row, value).
inline void append_columns(const SparseColumns& part, std::vector<int>& start, std::vector<int>& row, std::vector<double>& value) {
    const int at = static_cast<int>(row.size());
    row.insert(row.end(), part.row.begin(), part.row.end());
    value.insert(value.end(), part.value.begin(), part.value.end());
    for (int end : part.end) start.push_back(at + end);
}

/// Column q . v of a matrix stored by sparse columns ([start[q], start[q + 1]) of row, value; v dense).
inline double sparse_column_dot(const std::vector<int>& start, const std::vector<int>& row, const std::vector<double>& value,
                                int q, const Eigen::VectorXd& v) {
    double s = 0.0;
    for (int p = start[q]; p < start[q + 1]; ++p) s += value[p] * v[row[p]];
    return s;
}

struct FactorAugment {
    uint64_t topology = 0;            ///< the pattern of A it was last extended for
    int base = 0;                     ///< scalar rows of the factor (the old DOFs)
    std::vector<int> parent;          ///< per new scalar DOF: its mesh node's scalar DOF (jump basis), or -1
    /// Y = L^-1 P B by columns, one per new DOF: column k's rows and values are
    /// [y_start[k], y_start[k + 1]) of y_row, y_value.
    std::vector<int> y_start{0}, y_row;
    std::vector<double> y_value;
    Eigen::MatrixXd S;                ///< C - Y^T Y
    Eigen::LLT<Eigen::MatrixXd> schur;
    bool ok = false;                  ///< S was positive definite

    int columns() const { return static_cast<int>(parent.size()); }
    /// Y_q . v over column q's entries (v dense, in the factor's order).
    double column_dot(int q, const Eigen::VectorXd& v) const { return sparse_column_dot(y_start, y_row, y_value, q, v); }
};

/// Gives `to`, a factor's block not yet extended, the storage of `from`'s columns (the block of the
/// factor it replaces, no longer usable after: ok false, freed with its factor off the step): the
/// pages a cut's columns fill stay resident from factor to factor instead of being faulted in
/// again by the next split step.
inline void hand_on_columns(FactorAugment& from, FactorAugment& to) {
    std::swap(to.y_row, from.y_row), std::swap(to.y_value, from.y_value), std::swap(to.y_start, from.y_start);
    to.y_start.assign(1, 0), to.y_row.clear(), to.y_value.clear();
    from.ok = false;
}

/// Extends the augmented block to A's new DOFs (block rows [base/3, A.rows()) over the factor
/// `lf`; `parent` as FactorAugment::parent, for all of them). The columns of DOFs it already holds
/// are kept as they were computed (stale like the factor itself); only the DOFs new since are
/// solved for, with their rows and columns of S. False if S is not positive definite (the old
/// factor is too far from the grown system's old block): the caller factors A anew.
bool extend_augment(const LinearSystem& A, const LowerFactor& lf, std::vector<int> parent, FactorAugment& g);

// z = T M^-1 T^T r, M = [[L L^T, B], [B^T, C]] (the augmented preconditioner), is applied with a
// moving term's block or without: apply_augmented, systems/solver/beside_augment.h.

}  // namespace xcut
