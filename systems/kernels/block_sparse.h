#pragma once
// Block access to the step's 3x3-block sparse matrix (components/linear_system.h): finding block
// (i, j) in a row's sorted columns, and a block's values as a row-major 3x3 map.
#include <Eigen/Core>
#include <algorithm>

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

}  // namespace xcut
