#include "systems/solver/factor_background.h"

#include <algorithm>
#include <chrono>

#include "engine/background_threads.h"
#include "systems/solver/beside_augment.h"
#include "systems/solver/cholmod_pages.h"
#include "systems/solver/linear_assembly.h"
#include "systems/kernels/solver/block_sparse.h"

namespace xcut {
namespace {

/// The DOF node below `base` (a factor's nodes) that DOF node j was split from, through the
/// phantoms' chain of copies (j itself if it is below `base`).
int node_in_factor(const World& w, int j, int base) {
    while (j >= base) j = w.enriched.phantom_from[j - w.mesh_nodes];
    return j;
}

}  // namespace

std::shared_ptr<PendingFactor> start_background_factor(const LinearSystem& A, std::shared_ptr<FactorSnapshot> snapshot,
                                                       BesideBlock jumps, int requested_step, int due_step, double single_from) {
    if (!snapshot) snapshot = std::make_shared<FactorSnapshot>();
    copy_linear_system(A, snapshot->block);
    auto f = std::make_shared<LinearFactor>(true);
    f->topology = A.topology, f->computed_step = requested_step, f->snapshot = snapshot, f->single_from = single_from;
    f->jumps = std::move(jumps);
    auto pending = std::make_shared<PendingFactor>();
    pending->requested_step = requested_step, pending->due_step = due_step;
    pending->computing = f, pending->nodes = A.rows();
    pending->result = run_in_background<std::shared_ptr<LinearFactor>>([f]() {
        try {
            // The scalar copy is made and factored in the snapshot's storage, and left there for
            // the next factor (the views need CHOLMOD's L only).
            f->matrix.swap(f->snapshot->scalar);
            copy_to_scalar(f->snapshot->block, f->matrix, true);
            compute_factor(*f, true);
            f->matrix.swap(f->snapshot->scalar);
        } catch (const std::exception&) {  // out of memory: the step factors in itself
            f->ok = false;
        }
        return f;
    });
    return pending;
}

void start_successor_columns(const World& w, PendingFactor& p, const BesideAugment& b, const LinearFactor& in_use) {
    if (p.beside.valid() || !b.ok || b.unbuilt || b.factor != in_use.serial || !in_use.lower ||
        in_use.computed_step > p.requested_step)
        return;
    const int before = in_use.lower->rows() / 3;  // the nodes b's rows belong to
    std::vector<char> held(before, 0);
    std::vector<int> rows;
    for (int r : b.s_rows)
        if (r < 3 * p.nodes) rows.push_back(r), held[r / 3] = 1;
    for (int j = before; j < p.nodes; ++j) {  // split since: b stands for them by the node they came from
        if (held[node_in_factor(w, j, before)])
            for (int c = 0; c < 3; ++c) rows.push_back(3 * j + c);
    }
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    p.beside = run_in_background<std::shared_ptr<BesideAugment>>([f = p.computing, rows = std::move(rows)]() {
        auto made = std::make_shared<BesideAugment>();
        try {
            if (f->ok && f->lower) solve_beside_columns(*f->lower, f->serial, rows, *made);
        } catch (const std::exception&) {  // out of memory: the swap's block solves them
            made = std::make_shared<BesideAugment>();
        }
        return made;
    });
}

void take_successor_columns(PendingFactor& p, const LinearFactor& f, BesideAugment& b, double& wait_ms) {
    wait_ms = 0.0;
    if (!p.beside.valid()) return;
    const auto t0 = std::chrono::steady_clock::now();
    std::shared_ptr<BesideAugment> made = p.beside.get();
    wait_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (made->factor == f.serial && made->factor != 0) take_beside_columns(std::move(*made), b);
}

void retire_factor(std::shared_ptr<LinearFactor> f) {
    if (f) post_background_job([f = std::move(f)]() mutable { f.reset(); });
}

void warm_pages_for_successor(const LinearFactor& f) {
    const cholmod_factor* L = f.llt.factor();
    if (!L || !L->is_super) return;
    std::vector<size_t> sizes{L->xsize * sizeof(double), L->ssize * sizeof(int)};
    if (f.lower && f.lower->is_single()) sizes.push_back(f.lower->single.size() * sizeof(float));
    post_background_job([sizes = std::move(sizes)] { keep_touched_blocks(sizes); });
}

bool augment_for_grown_system(const World& w, LinearFactor& f, const Eigen::VectorXd& mask) {
    const LinearSystem& A = w.linear;
    if (f.augment.ok && f.augment.topology == A.topology) return true;
    if (!f.lower) return false;
    const int base_nodes = f.lower->rows() / 3;
    // A snapping remesh moves the old nodes' elements: no jump basis, the old block is not kept.
    if (w.snap.elements_split > 0 || base_nodes < w.mesh_nodes || A.rows() < base_nodes) return false;
    std::vector<int> parent;  // per new scalar DOF: its mesh node's, both axes free; else -1
    for (int j = base_nodes; j < A.rows(); ++j) {
        const int phantom = j - w.mesh_nodes;
        if (phantom >= w.enriched.count()) return false;
        const int node = node_in_factor(w, j, base_nodes);  // the copy it split from, in the old block
        for (int c = 0; c < 3; ++c)
            parent.push_back(mask[3 * node + c] != 0.0 && mask[3 * j + c] != 0.0 ? 3 * node + c : -1);
    }
    return extend_augment(A, *f.lower, std::move(parent), f.augment);
}

}  // namespace xcut
