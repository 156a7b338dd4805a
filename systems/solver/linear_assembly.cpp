#include "systems/solver/linear_assembly.h"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

#include "engine/parallel.h"
#include "engine/vector_room.h"
#include "systems/kernels/solver/block_sparse.h"

namespace xcut {
namespace {

/// FNV-1a over the element node ids: the pattern is rebuilt when it changes.
uint64_t topology_hash(const World& w) {
    uint64_t h = 1469598103934665603ull ^ static_cast<uint64_t>(w.nodes.count());
    for (const auto& n : w.elements.nodes)
        for (int id : n) h = (h ^ static_cast<uint64_t>(static_cast<uint32_t>(id))) * 1099511628211ull;
    for (const auto& n : w.quadratic.nodes)
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

/// Calls f(k, t) for every entry k of node i in the quadratic elements' incidence (t: the element).
template <class F>
void for_quadratic(const World& w, int i, F&& f) {
    const Incidence& inc = w.quadratic.incidence;
    if (i + 1 >= static_cast<int>(inc.offset.size())) return;
    for (int k = inc.offset[i]; k < inc.offset[i + 1]; ++k) f(k, inc.entry[k] >> 4);
}

int quadratic_incident(const World& w, int i) {
    int n = 0;
    for_quadratic(w, i, [&](int, int) { ++n; });
    return n;
}

}  // namespace

bool ensure_linear_pattern(World& w) {
    LinearSystem& A = w.linear;
    const uint64_t topology = topology_hash(w);
    if (topology == A.topology && A.rows() == w.nodes.count()) return false;
    const int n = w.nodes.count(), npe = w.elements.nodes_per_element();
    // Each row's candidate columns (the nodes of its incident elements and itself) go to their own
    // stretch of one flat buffer, kept between rebuilds: no allocation per row, and the rows are
    // sorted in parallel without contending for the allocator.
    std::vector<int>& bound = A.pattern_bound;
    std::vector<int>& flat = A.pattern_scratch;
    resize_with_room(bound, static_cast<size_t>(n) + 1);
    bound[0] = 0;
    for (int i = 0; i < n; ++i) {
        int incident = w.virtual_incidence.offset[i + 1] - w.virtual_incidence.offset[i];
        if (i < w.mesh_nodes) incident += w.incidence.offset[i + 1] - w.incidence.offset[i];
        bound[i + 1] = bound[i] + npe * incident + 10 * quadratic_incident(w, i) + 1;
    }
    resize_with_room(flat, static_cast<size_t>(bound[n]));
    resize_with_room(A.row_offset, static_cast<size_t>(n) + 1);
    parallel_for(n, [&](int i) {
        int* first = flat.data() + bound[i];
        int* last = first;
        for_incident(w, i, [&](bool, int, int entry) {
            for (int b = 0; b < npe; ++b) *last++ = w.elements.nodes[entry >> 2][b];
        });
        for_quadratic(w, i, [&](int, int t) { last = std::copy(w.quadratic.nodes[t].begin(), w.quadratic.nodes[t].end(), last); });
        *last++ = i;
        std::sort(first, last);
        A.row_offset[i + 1] = static_cast<int>(std::unique(first, last) - first);
    }, 256);
    A.row_offset[0] = 0;
    for (int i = 0; i < n; ++i) A.row_offset[i + 1] += A.row_offset[i];
    resize_with_room(A.column, static_cast<size_t>(A.row_offset[n]));
    resize_with_room(A.diagonal, static_cast<size_t>(n));
    parallel_for(n, [&](int i) {
        std::copy(flat.begin() + bound[i], flat.begin() + bound[i] + (A.row_offset[i + 1] - A.row_offset[i]),
                  A.column.begin() + A.row_offset[i]);
    }, 256);
    resize_with_room(A.mesh_slot, w.incidence.entry.size());
    resize_with_room(A.virtual_slot, w.virtual_incidence.entry.size());
    resize_with_room(A.quadratic_slot, w.quadratic.incidence.entry.size());
    parallel_for(n, [&](int i) {
        A.diagonal[i] = find_block(A, i, i);
        for_incident(w, i, [&](bool virt, int k, int entry) {
            auto& slot = virt ? A.virtual_slot[k] : A.mesh_slot[k];
            slot = {-1, -1, -1, -1};
            for (int b = 0; b < npe; ++b) slot[b] = find_block(A, i, w.elements.nodes[entry >> 2][b]);
        });
        for_quadratic(w, i, [&](int k, int t) {
            for (int b = 0; b < 10; ++b) A.quadratic_slot[k][b] = find_block(A, i, w.quadratic.nodes[t][b]);
        });
    }, 1024);
    resize_with_room(A.value, 9 * A.column.size());
    std::fill(A.value.begin(), A.value.end(), 0.0);
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
        if (!t->by_rows() && !t->beside_assembly() && t->active(w)) t->add_scattered(w, stiff_scale, A);
    filter_held_axes(w, A);
}

void copy_linear_system(const LinearSystem& A, LinearSystem& into) {
    if (into.topology != A.topology || into.value.size() != A.value.size()) {
        assign_with_room(into.row_offset, A.row_offset), assign_with_room(into.column, A.column);
        assign_with_room(into.diagonal, A.diagonal);
        into.topology = A.topology;
    }
    assign_with_room(into.value, A.value);
}

}  // namespace xcut
