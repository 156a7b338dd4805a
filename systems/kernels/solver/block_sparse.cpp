#include "systems/kernels/solver/block_sparse.h"

#include <Eigen/LU>
#include <algorithm>

#include "engine/parallel.h"

namespace xcut {

void linear_multiply_rows(const LinearSystem& A, int lo, int hi, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    for (int i = lo; i < hi; ++i) {
        Eigen::Vector3d s = Eigen::Vector3d::Zero();
        for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
            s += Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(A.value.data() + 9 * b) *
                 x.segment<3>(3 * A.column[b]);
        y.segment<3>(3 * i) = s;
    }
}

void linear_multiply(const LinearSystem& A, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    y.resize(3 * A.rows());
    parallel_for(A.rows(), [&](int i) { linear_multiply_rows(A, i, i + 1, x, y); }, 2048);
}

namespace {

/// Columns [first, first + width) of AV = A V; Width is the count, or Eigen::Dynamic (width given).
template <int Width>
void multiply_columns(const LinearSystem& A, const Eigen::MatrixXd& V, int first, int width, Eigen::MatrixXd& AV) {
    using Block = Eigen::Matrix<double, 3, Width, Eigen::ColMajor, 3, Width == Eigen::Dynamic ? 6 : Width>;
    parallel_for(A.rows(), [&](int i) {
        Block sum = Block::Zero(3, width);
        for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b)
            sum.noalias() += Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(A.value.data() + 9 * b) *
                             V.block(3 * A.column[b], first, 3, width);
        AV.block(3 * i, first, 3, width) = sum;
    }, 2048);
}

}  // namespace

void linear_multiply_columns(const LinearSystem& A, const Eigen::MatrixXd& V, Eigen::MatrixXd& AV) {
    constexpr int kAtOnce = 6;
    AV.resize(3 * A.rows(), V.cols());
    for (int first = 0; first < V.cols(); first += kAtOnce) {
        const int width = std::min<int>(kAtOnce, static_cast<int>(V.cols()) - first);
        if (width == kAtOnce) multiply_columns<kAtOnce>(A, V, first, width, AV);
        else multiply_columns<Eigen::Dynamic>(A, V, first, width, AV);
    }
}

void block_diagonal_inverse(const LinearSystem& A, std::vector<double>& inverse) {
    inverse.resize(9 * A.rows());
    parallel_for(A.rows(), [&](int i) {
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> d(A.value.data() + 9 * A.diagonal[i]);
        Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(inverse.data() + 9 * i) = d.inverse();
    }, 2048);
}

}  // namespace xcut
