#pragma once
// The cholesky method's factor renewed off the step, so that no step stalls on a factorization
// (Courtecuisse et al. 2014, "Real-time simulation of contact and cutting of heterogeneous
// soft-tissues": the preconditioner is updated asynchronously; Yeung, Crouch & Pothen 2016: the old
// factor solves the grown system through an augmented block meanwhile).
//  - At a cut (an XFEM split adds phantom DOFs), the factor in use goes on for the grown system
//    through an augmented block (systems/solver/factor_augment.h), extended in the step by the new
//    DOFs' columns.
//  - A successor is asked for when CG needs more than half of solver.refactor_iterations, when the
//    factor is solver.refactor_every steps old, or when the augmented block holds 120 DOFs; the
//    factor in use goes on meanwhile. It is renewed in the step only past 4x refactor_iterations,
//    after a failed solve, or after a snapping remesh (no jump basis there).
// It is started once the asking step has solved (from the same A: that step's CG keeps both threads,
// where a job already running leaves the team one fewer).
// The successor is computed on the background thread (engine/background_threads.h) from a copy of
// the step's A (CHOLMOD's supernodal factor, under with_cholmod_blas: only that thread calls BLAS,
// since the step solves through views of the supernodes, systems/solver/lower_factor.h) and taken
// at the first solve of the step solver.factor_delay steps after it was asked for: a fixed step,
// never "whenever the thread finishes", so results do not depend on the machine's load. That step
// waits for it if it is not ready, and the wait is measured (LinearSystem::step_wait_ms). A
// successor that failed (not SPD) is replaced by a factor computed in that step, as a failed
// factorization always was. Two factors live at once only between the request and the swap.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

#include "engine/world.h"
#include "systems/solver/background_result.h"
#include "systems/solver/beside_augment.h"
#include "systems/solver/cholesky_factor.h"

namespace xcut {

/// A factor being computed off the step (taken by take_when_due, systems/solver/background_result.h).
struct PendingFactor : PendingResult<LinearFactor> {
    std::shared_ptr<LinearFactor> computing;  ///< the factor the job makes (for jobs posted after it)
    int nodes = 0;                            ///< A's DOF nodes when it was asked for (its rows / 3)
    /// The columns of X_S a moving block will need over it (start_successor_columns), if asked for.
    std::future<std::shared_ptr<BesideAugment>> beside;
};

/// Starts computing a factor of A, to be solved through views of its supernodes, due at `due_step`.
/// A is copied into `snapshot` (storage handed on from factor to factor, or null): it changes from
/// the next step on. `jumps`: the jumping terms' block A holds now (LinearFactor::jumps).
std::shared_ptr<PendingFactor> start_background_factor(const LinearSystem& A, std::shared_ptr<FactorSnapshot> snapshot,
                                                       BesideBlock jumps, int requested_step, int due_step, double single_from);
/// The steps before a successor is due at which the columns of X_S its moving block will need are
/// asked for: the block's rows then, most of those it has at the swap (a front moves a few rows a
/// step), so that the step that takes the factor solves only the rows new since.
constexpr int kSuccessorColumnsLead = 2;
/// Asks the background thread (after p's factor job) for the columns of X_S over p's factor for the
/// rows of b (built over `in_use`, the factor p is to replace) and of the DOF nodes split, between
/// the two factors' DOFs, from the nodes of those rows (which b's rows stand for). Once per p; not
/// when b is not built over `in_use`. The swap's block keeps them (the same bits as solved there:
/// systems/solver/beside_augment.h).
void start_successor_columns(const World& w, PendingFactor& p, const BesideAugment& b, const LinearFactor& in_use);
/// Gives b the columns made for f, the factor just taken from p (waiting for them: wait_ms [ms]).
void take_successor_columns(PendingFactor& p, const LinearFactor& f, BesideAugment& b, double& wait_ms);

/// Lets the background thread free a factor no longer in use (its pages given back off the step).
void retire_factor(std::shared_ptr<LinearFactor> f);

/// Makes blocks the size of f's largest arrays (L's values and row indices, their single-precision
/// copy) resident in CHOLMOD's kept pages, on the background thread: the first successor of the
/// factor made at load, computed while the one in use still holds its own, would otherwise
/// allocate them in fresh pages (the skin at 1 mm: 185 ms of the background thread's CPU time for
/// that first successor against 85-110 ms for the later ones, which reuse a retired factor's).
void warm_pages_for_successor(const LinearFactor& f);

/// Builds f.augment for world.linear when A grew from f's DOFs by phantom nodes only (an XFEM
/// split; a snapping remesh is not) and f has views of its supernodes; true if f now solves A
/// through it.
bool augment_for_grown_system(const World& world, LinearFactor& f, const Eigen::VectorXd& mask);

}  // namespace xcut
