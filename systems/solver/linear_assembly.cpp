#include "systems/solver/linear_assembly.h"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

#include "engine/parallel.h"
#include "systems/kernels/solver/block_sparse.h"

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

}  // namespace xcut
