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

/// An upper bound of block row i's columns: its incident elements' nodes, and itself.
int row_bound(const World& w, int i, int npe) {
    int incident = w.virtual_incidence.offset[i + 1] - w.virtual_incidence.offset[i];
    if (i < w.mesh_nodes) incident += w.incidence.offset[i + 1] - w.incidence.offset[i];
    return npe * incident + 10 * quadratic_incident(w, i) + 1;
}

/// Writes block row i's columns (sorted, each once) from `first`; returns how many.
int gather_row(const World& w, int i, int npe, int* first) {
    int* last = first;
    for_incident(w, i, [&](bool, int, int entry) {
        for (int b = 0; b < npe; ++b) *last++ = w.elements.nodes[entry >> 2][b];
    });
    for_quadratic(w, i, [&](int, int t) { last = std::copy(w.quadratic.nodes[t].begin(), w.quadratic.nodes[t].end(), last); });
    *last++ = i;
    std::sort(first, last);
    return static_cast<int>(std::unique(first, last) - first);
}

/// Block row i's diagonal and its incidence entries' slots, searched in its columns.
void place_row(const World& w, LinearSystem& A, int i, int npe) {
    A.diagonal[i] = find_block(A, i, i);
    for_incident(w, i, [&](bool virt, int k, int entry) {
        auto& slot = virt ? A.virtual_slot[k] : A.mesh_slot[k];
        slot = {-1, -1, -1, -1};
        for (int b = 0; b < npe; ++b) slot[b] = find_block(A, i, w.elements.nodes[entry >> 2][b]);
    });
    for_quadratic(w, i, [&](int k, int t) {
        for (int b = 0; b < 10; ++b) A.quadratic_slot[k][b] = find_block(A, i, w.quadratic.nodes[t][b]);
    });
}

/// The rows marked in A.pattern.changed gathered into the flat scratch (the others take their old
/// count from `old_offset`), then A.row_offset as the prefix sum and A.column filled, each row from
/// the scratch or `old_column`.
void lay_out_rows(const World& w, LinearSystem& A, const std::vector<int>& old_offset, const std::vector<int>& old_column) {
    PatternBuild& p = A.pattern;
    const int n = w.nodes.count(), npe = w.elements.nodes_per_element();
    resize_with_room(p.bound, static_cast<size_t>(n) + 1);
    p.bound[0] = 0;
    for (int i = 0; i < n; ++i) p.bound[i + 1] = p.bound[i] + (p.changed[i] ? row_bound(w, i, npe) : 0);
    resize_with_room(p.scratch, static_cast<size_t>(p.bound[n]));
    resize_with_room(A.row_offset, static_cast<size_t>(n) + 1);
    parallel_for(n, [&](int i) {
        A.row_offset[i + 1] = p.changed[i] ? gather_row(w, i, npe, p.scratch.data() + p.bound[i]) : old_offset[i + 1] - old_offset[i];
    }, 256);
    A.row_offset[0] = 0;
    for (int i = 0; i < n; ++i) A.row_offset[i + 1] += A.row_offset[i];
    resize_with_room(A.column, static_cast<size_t>(A.row_offset[n]));
    parallel_for(n, [&](int i) {
        const auto from = p.changed[i] ? p.scratch.begin() + p.bound[i] : old_column.begin() + old_offset[i];
        std::copy(from, from + (A.row_offset[i + 1] - A.row_offset[i]), A.column.begin() + A.row_offset[i]);
    }, 256);
}

/// The whole pattern gathered and searched.
void build_whole_pattern(World& w) {
    LinearSystem& A = w.linear;
    const int n = w.nodes.count(), npe = w.elements.nodes_per_element();
    A.pattern.changed.assign(n, 1);
    lay_out_rows(w, A, A.pattern.row_offset, A.pattern.column);
    resize_with_room(A.diagonal, static_cast<size_t>(n));
    resize_with_room(A.mesh_slot, w.incidence.entry.size());
    resize_with_room(A.virtual_slot, w.virtual_incidence.entry.size());
    resize_with_room(A.quadratic_slot, w.quadratic.incidence.entry.size());
    parallel_for(n, [&](int i) { place_row(w, A, i, npe); }, 1024);
}

/// After a split (the mesh's elements as they were, virtual elements changed or added, nodes
/// added): the rows of the changed elements' nodes, old and new, and the new nodes' rows gathered
/// and searched; every other row keeps its columns, its blocks shifted by how far its row moved.
/// False (nothing changed) where that does not apply: no pattern yet, quadratic elements, fewer
/// nodes or elements than at the build, or a mesh element changed (a snapping remesh).
bool rebuild_changed_rows(World& w) {
    LinearSystem& A = w.linear;
    PatternBuild& p = A.pattern;
    const int n = w.nodes.count(), old_n = A.rows(), npe = w.elements.nodes_per_element();
    const auto& el = w.elements.nodes;
    if (A.topology == 0 || !w.quadratic.nodes.empty() || n < old_n || w.mesh_nodes != p.mesh_nodes ||
        w.mesh_elements != p.mesh_elements || el.size() < p.elements.size() || p.virtual_offset.size() != static_cast<size_t>(old_n) + 1)
        return false;
    p.changed.assign(n, 0);
    std::fill(p.changed.begin() + old_n, p.changed.end(), 1);
    for (size_t e = 0; e < el.size(); ++e) {
        if (e < p.elements.size() && el[e] == p.elements[e]) continue;
        if (static_cast<int>(e) < w.mesh_elements) return false;
        for (int b = 0; b < npe; ++b) {
            p.changed[el[e][b]] = 1;
            if (e < p.elements.size()) p.changed[p.elements[e][b]] = 1;
        }
    }
    std::swap(A.row_offset, p.row_offset), std::swap(A.column, p.column), std::swap(A.diagonal, p.diagonal);
    std::swap(A.virtual_slot, p.virtual_slot);
    lay_out_rows(w, A, p.row_offset, p.column);
    resize_with_room(A.diagonal, static_cast<size_t>(n));
    resize_with_room(A.virtual_slot, w.virtual_incidence.entry.size());
    const std::vector<int>& voffset = w.virtual_incidence.offset;
    parallel_for(n, [&](int i) {
        if (p.changed[i]) return place_row(w, A, i, npe);
        const int shift = A.row_offset[i] - p.row_offset[i];
        A.diagonal[i] = p.diagonal[i] + shift;
        for_incident(w, i, [&](bool virt, int k, int) {
            auto& slot = virt ? A.virtual_slot[k] : A.mesh_slot[k];
            if (virt) slot = p.virtual_slot[p.virtual_offset[i] + k - voffset[i]];
            for (int b = 0; b < npe; ++b) slot[b] += shift;
        });
    }, 1024);
    ++p.carried;
    return true;
}

}  // namespace

bool ensure_linear_pattern(World& w) {
    LinearSystem& A = w.linear;
    const uint64_t topology = topology_hash(w);
    if (topology == A.topology && A.rows() == w.nodes.count()) return false;
    if (!rebuild_changed_rows(w)) build_whole_pattern(w);
    PatternBuild& p = A.pattern;
    assign_with_room(p.elements, w.elements.nodes), assign_with_room(p.virtual_offset, w.virtual_incidence.offset);
    p.mesh_nodes = w.mesh_nodes, p.mesh_elements = w.mesh_elements;
    // Unset: assemble_step_matrix sets each row (zeroed first) before any solve reads it (a split
    // of the 200k-tet block spent 1.7-2 ms zeroing them here).
    resize_with_room(A.value, 9 * A.column.size());
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
