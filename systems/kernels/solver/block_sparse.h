#pragma once
// Block access to the step's 3x3-block sparse matrix (components/linear_system.h): finding block
// (i, j) in a row's sorted columns, a block's values as a row-major 3x3 map, the products (one
// thread per block row, each row summed in column order: the same bits for any thread count), the
// block diagonal's inverse, and the scalar copy a sparse factorization or a multigrid setup takes.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <vector>

#include "components/linear_system.h"

namespace xcut {

/// The index of block (i, j) in A's pattern, or -1.
inline int find_block(const LinearSystem& A, int i, int j) {
    const auto begin = A.column.begin() + A.row_offset[i], end = A.column.begin() + A.row_offset[i + 1];
    const auto it = std::lower_bound(begin, end, j);
    return it != end && *it == j ? static_cast<int>(it - A.column.begin()) : -1;
}

/// Block b's nine values, row-major.
inline Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> block_at(LinearSystem& A, int b) {
    return Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(A.value.data() + 9 * b);
}

/// y = A x for the assembled A (3 entries per DOF node).
void linear_multiply(const LinearSystem& A, const Eigen::VectorXd& x, Eigen::VectorXd& y);
/// AV = A V, every column of V in one pass over A (six at a time): each column's sums are
/// linear_multiply's, in its order. Six separate products took 1.3-1.7 ms at 53k tets, this 0.85-1.1.
void linear_multiply_columns(const LinearSystem& A, const Eigen::MatrixXd& V, Eigen::MatrixXd& AV);
/// The block rows [lo, hi) of y = A x (y sized by the caller), on the calling thread.
void linear_multiply_rows(const LinearSystem& A, int lo, int hi, const Eigen::VectorXd& x, Eigen::VectorXd& y);

/// The inverses of A's 3x3 diagonal blocks, 9 per node (row-major): the block Jacobi preconditioner.
void block_diagonal_inverse(const LinearSystem& A, std::vector<double>& inverse);

/// The scalar matrix of A: row 3i + r holds, block by block in column order, entries 3j + c.
/// Symmetric, so its CSR arrays are its CSC ones: either storage order takes them. `structure`:
/// (re)build the pattern too, else refill the values only.
/// Room a scalar copy's arrays are given beyond their entries when they grow (an eighth), so that
/// a copy made again after a cut (a few more DOFs) fills the same pages instead of fresh ones.
inline constexpr double kScalarCopyRoom = 0.125;

template <class Sparse>
void copy_to_scalar(const LinearSystem& A, Sparse& S, bool structure) {
    const int n = A.rows();
    if (structure) {
        S.resize(3 * n, 3 * n);  // keeps the arrays' storage: a copy made again reuses their pages
        S.data().resize(9 * A.blocks(), kScalarCopyRoom);
        int* outer = S.outerIndexPtr();
        int* inner = S.innerIndexPtr();
        outer[0] = 0;
        for (int i = 0; i < n; ++i) {
            const int width = 3 * (A.row_offset[i + 1] - A.row_offset[i]);
            for (int r = 0; r < 3; ++r) {
                int at = outer[3 * i + r];
                for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
                    for (int c = 0; c < 3; ++c) inner[at++] = 3 * A.column[b] + c;
                outer[3 * i + r + 1] = outer[3 * i + r] + width;
            }
        }
    }
    double* value = S.valuePtr();
    const int* outer = S.outerIndexPtr();
    for (int i = 0; i < n; ++i)
        for (int r = 0; r < 3; ++r) {
            int at = outer[3 * i + r];
            for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
                for (int c = 0; c < 3; ++c) value[at++] = A.value[9 * b + 3 * r + c];
        }
}

}  // namespace xcut
