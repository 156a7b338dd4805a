#include "systems/solver/factor_background.h"

#include "engine/background_threads.h"
#include "systems/solver/beside_augment.h"
#include "systems/solver/linear_assembly.h"
#include "systems/kernels/solver/block_sparse.h"

namespace xcut {

std::shared_ptr<PendingFactor> start_background_factor(const LinearSystem& A, std::shared_ptr<LinearSystem> snapshot,
                                                       BesideBlock jumps, int requested_step, int due_step) {
    if (!snapshot) snapshot = std::make_shared<LinearSystem>();
    copy_linear_system(A, *snapshot);
    auto f = std::make_shared<LinearFactor>(true);
    f->topology = A.topology, f->computed_step = requested_step, f->snapshot = snapshot;
    f->jumps = std::move(jumps);
    auto pending = std::make_shared<PendingFactor>();
    pending->requested_step = requested_step, pending->due_step = due_step;
    pending->result = run_in_background<std::shared_ptr<LinearFactor>>([f]() {
        try {
            copy_to_scalar(*f->snapshot, f->matrix, true);
            compute_factor(*f, true);
        } catch (const std::exception&) {  // out of memory: the step factors in itself
            f->ok = false;
        }
        return f;
    });
    return pending;
}

void retire_factor(std::shared_ptr<LinearFactor> f) {
    if (f) post_background_job([f = std::move(f)]() mutable { f.reset(); });
}

bool augment_for_grown_system(const World& w, LinearFactor& f, const Eigen::VectorXd& mask) {
    const LinearSystem& A = w.linear;
    const int base_nodes = static_cast<int>(f.matrix.rows()) / 3;
    if (f.augment.ok && f.augment.topology == A.topology) return true;
    // A snapping remesh moves the old nodes' elements: no jump basis, the old block is not kept.
    if (!f.lower || w.snap.elements_split > 0 || base_nodes < w.mesh_nodes || A.rows() < base_nodes) return false;
    std::vector<int> parent;  // per new scalar DOF: its mesh node's, both axes free; else -1
    for (int j = base_nodes; j < A.rows(); ++j) {
        const int phantom = j - w.mesh_nodes;
        if (phantom >= w.enriched.count()) return false;
        int node = w.enriched.phantom_from[phantom];  // the copy it split from, in the old block
        while (node >= base_nodes) node = w.enriched.phantom_from[node - w.mesh_nodes];
        for (int c = 0; c < 3; ++c)
            parent.push_back(mask[3 * node + c] != 0.0 && mask[3 * j + c] != 0.0 ? 3 * node + c : -1);
    }
    return extend_augment(A, *f.lower, std::move(parent), f.augment);
}

}  // namespace xcut
