#include "systems/solver/amg_background.h"

#include <chrono>

namespace xcut {

std::shared_ptr<PendingHierarchy> start_background_hierarchy(const LinearSystem& A, const std::vector<Eigen::Vector3d>& position,
                                                             const Eigen::VectorXd& mask, double ratio, int requested_step,
                                                             int due_step) {
    // Copies, on the step's thread: A, the positions and the mask change from the next step on.
    auto matrix = std::make_shared<LinearSystem>();
    matrix->row_offset = A.row_offset, matrix->column = A.column, matrix->diagonal = A.diagonal;
    matrix->value = A.value, matrix->topology = A.topology;
    auto pending = std::make_shared<PendingHierarchy>();
    pending->requested_step = requested_step, pending->due_step = due_step;
    pending->result = std::async(std::launch::async, [matrix, position, mask, ratio]() {
        auto h = std::make_shared<AmgHierarchy>();
        try {
            build_amg(*matrix, position, mask, *h);
            h->stiffness_ratio = ratio;
        } catch (const std::exception&) {  // out of memory: the step goes on with the old hierarchy
            h->ok = false;
        }
        return h;
    });
    return pending;
}

std::shared_ptr<AmgHierarchy> take_background_hierarchy(PendingHierarchy& pending, double& wait_ms) {
    const auto t0 = std::chrono::steady_clock::now();
    std::shared_ptr<AmgHierarchy> h = pending.result.get();
    wait_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return h;
}

}  // namespace xcut
