#include "systems/solver/linear_assembly.h"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

#include "engine/parallel.h"
#include "systems/kernels/block_sparse.h"

namespace xcut {
namespace {

/// FNV-1a over the element node ids: the pattern is rebuilt when it changes.
uint64_t topology_hash(const World& w) {
    uint64_t h = 1469598103934665603ull ^ static_cast<uint64_t>(w.nodes.count());
    for (const auto& n : w.elements.nodes)
        for (int id : n) h = (h ^ static_cast<uint64_t>(static_cast<uint32_t>(id))) * 1099511628211ull;
    return h;
}

/// Held axes: their rows and columns are dropped and their diagonal set to 1.
void filter_held_axes(const World& w, LinearSystem& A) {
    const auto& fixed = w.nodes.fixed;
    parallel_for(A.rows(), [&](int i) {
        for (int b = A.row_offset[i]; b < A.row_offset[i + 1]; ++b) {
            const int j = A.column[b];
            if (!fixed[i] && !fixed[j]) continue;
            auto blk = block_at(A, b);
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    if (((fixed[i] >> r) & 1) || ((fixed[j] >> c) & 1)) blk(r, c) = (i == j && r == c) ? 1.0 : 0.0;
        }
    });
}

}  // namespace

bool ensure_linear_pattern(World& w) {
    LinearSystem& A = w.linear;
    const uint64_t topology = topology_hash(w);
    if (topology == A.topology && A.rows() == w.nodes.count()) return false;
    const int n = w.nodes.count(), npe = w.elements.nodes_per_element();
    std::vector<std::vector<int>> columns(n);
    parallel_for(n, [&](int i) {
        std::vector<int>& cols = columns[i];
        for_incident(w, i, [&](bool, int, int entry) {
            for (int b = 0; b < npe; ++b) cols.push_back(w.elements.nodes[entry >> 2][b]);
        });
        cols.push_back(i);
        std::sort(cols.begin(), cols.end());
        cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    }, 1024);
    A.row_offset.assign(n + 1, 0);
    for (int i = 0; i < n; ++i) A.row_offset[i + 1] = A.row_offset[i] + static_cast<int>(columns[i].size());
    A.column.resize(A.row_offset[n]);
    A.diagonal.resize(n);
    for (int i = 0; i < n; ++i) std::copy(columns[i].begin(), columns[i].end(), A.column.begin() + A.row_offset[i]);
    A.mesh_slot.assign(w.incidence.entry.size(), {-1, -1, -1, -1});
    A.virtual_slot.assign(w.virtual_incidence.entry.size(), {-1, -1, -1, -1});
    parallel_for(n, [&](int i) {
        A.diagonal[i] = find_block(A, i, i);
        for_incident(w, i, [&](bool virt, int k, int entry) {
            auto& slot = virt ? A.virtual_slot[k] : A.mesh_slot[k];
            for (int b = 0; b < npe; ++b) slot[b] = find_block(A, i, w.elements.nodes[entry >> 2][b]);
        });
    }, 1024);
    A.value.assign(9 * A.column.size(), 0.0);
    A.topology = topology;
    return true;
}

void assemble_step_matrix(World& w, const StepOperator& op, double mass_scale, double stiff_scale) {
    LinearSystem& A = w.linear;
    for (const auto& t : op.terms)
        if (t->by_rows()) t->prepare_rows(w, stiff_scale);
    parallel_for(A.rows(), [&](int i) {
        std::fill(A.value.begin() + 9 * A.row_offset[i], A.value.begin() + 9 * A.row_offset[i + 1], 0.0);
        for (const auto& t : op.terms)
            if (t->by_rows()) t->add_row(w, i, A);
        block_at(A, A.diagonal[i]).diagonal().array() += mass_scale * w.nodes.mass[i];
    }, 512);
    for (const auto& t : op.terms)
        if (!t->by_rows() && t->active(w)) t->add_scattered(w, stiff_scale, A);
    filter_held_axes(w, A);
}

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
