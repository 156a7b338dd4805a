#include "systems/solver/amg_background.h"

#include "engine/background_threads.h"
#include "systems/solver/linear_assembly.h"

namespace xcut {

std::shared_ptr<PendingHierarchy> start_background_hierarchy(const LinearSystem& A, std::shared_ptr<LinearSystem> snapshot,
                                                             const std::vector<Eigen::Vector3d>& position,
                                                             const Eigen::VectorXd& mask, double ratio, int requested_step,
                                                             int due_step) {
    // Copies, on the step's thread: A, the positions and the mask change from the next step on.
    // A's copy goes into the storage of the one the kept hierarchy was built from, if any.
    auto matrix = snapshot ? std::move(snapshot) : std::make_shared<LinearSystem>();
    copy_linear_system(A, *matrix);
    auto pending = std::make_shared<PendingHierarchy>();
    pending->requested_step = requested_step, pending->due_step = due_step;
    pending->result = run_in_background<std::shared_ptr<AmgHierarchy>>([matrix, position, mask, ratio]() {
        auto h = std::make_shared<AmgHierarchy>();
        try {
            build_amg(*matrix, position, mask, *h);
            h->stiffness_ratio = ratio;
            h->snapshot = matrix;
        } catch (const std::exception&) {  // out of memory: the step goes on with the old hierarchy
            h->ok = false;
        }
        return h;
    });
    return pending;
}


}  // namespace xcut
