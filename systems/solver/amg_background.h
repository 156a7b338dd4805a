#pragma once
// The amg method's hierarchy renewed off the step (Courtecuisse et al. 2014, "Real-time simulation
// of contact and cutting of heterogeneous soft-tissues": the preconditioner is rebuilt
// asynchronously, and the simulation does not wait for it). When the kept policy says the hierarchy
// has aged (CG needs twice its first count, or it is solver.refactor_every steps old), the step
// asks for a new one, built on the background thread (engine/background_threads.h) from copies of
// that step's matrix, positions and held axes once that step has solved (its CG keeps both
// threads), and goes on with the old one. The new one is taken
// at the first solve of the step solver.renew_delay steps later: a fixed step, never "whenever the
// thread finishes", so results do not depend on the machine's load. That step waits for it if it
// is not ready, and the wait is measured (LinearSystem::step_wait_ms). The setup is
// single-threaded Eigen code (no BLAS, no OpenMP: systems/kernels/solver/amg.h), so it runs beside
// the step's own threads safely.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "components/linear_system.h"
#include "systems/kernels/solver/amg.h"
#include "systems/solver/background_result.h"

namespace xcut {

/// A hierarchy being built off the step, taken with take_when_due (systems/solver/background_result.h).
/// A setup that failed (its coarsest factor not SPD, out of memory) comes back with ok false.
struct PendingHierarchy : PendingResult<AmgHierarchy> {};

/// Starts building a hierarchy for A (its pattern and values now), `position` and `mask`, for
/// stiff_scale / mass_scale = `ratio`, due at `due_step`. A is copied into `snapshot` (the copy the
/// kept hierarchy was built from, AmgHierarchy::snapshot, or null): it changes from the next step on.
std::shared_ptr<PendingHierarchy> start_background_hierarchy(const LinearSystem& A, std::shared_ptr<LinearSystem> snapshot,
                                                             const std::vector<Eigen::Vector3d>& position,
                                                             const Eigen::VectorXd& mask, double ratio, int requested_step,
                                                             int due_step);

}  // namespace xcut
