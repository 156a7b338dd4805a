#pragma once
// The linear-solver stage of the implicit step: one interface, several methods, chosen in the scene
// by `solver.linear` (SOFA's split of a linear system from its solver, without its machinery):
//  - "jacobi": matrix-free CG with the diagonal of A (the paper's setting; no assembly, least memory);
//  - "block_jacobi": CG on the assembled A (systems/solver/linear_assembly.h) with its 3x3 diagonal blocks
//    inverted: cheap per iteration, least memory of the assembled methods;
//  - "cholesky": CG preconditioned by a CHOLMOD Cholesky factor of an earlier step's A (Chen,
//    Davis, Hager & Rajamanickam, ACM TOMS 35(3), 2008; systems/solver/cholesky_factor.h).
//    Rotations change slowly, so an old factor stays a near-exact inverse: 1-5 iterations. A cut's
//    new DOFs are solved through an augmented block on the old factor (systems/solver/factor_augment.h);
//    the factor is renewed off the step (systems/solver/factor_background.h) when CG needs more
//    than half of `solver.refactor_iterations`, when it is `solver.refactor_every` steps old, or
//    when the block holds 120 DOFs, and taken `solver.factor_delay` steps later; with
//    factor_delay 0, or after a snapping remesh, in the step. The step at which a new factor is taken
//    depends only on the steps and the iteration counts, never on timing: replays stay bit-identical;
//  - "direct": a supernodal factor computed every step (CG then converges in one or two iterations);
//  - "amg": CG preconditioned by a smoothed-aggregation multigrid V-cycle (systems/kernels/solver/amg.h),
//    10-20 iterations at any size; the hierarchy is kept, carried over to the new DOFs at a cut
//    (no setup at the cut step), and renewed when CG needs twice its first count or when it is
//    `solver.refactor_every` steps old: off the step, built on the background thread and taken
//    `solver.renew_delay` steps later (systems/solver/amg_background.h); in the step when the
//    step's stiffness weight grows (the kept smoother's bounds would not hold) or renew_delay is 0;
//  - "auto": cholesky up to 10,000 DOFs while its factor's estimated memory fits in a quarter of
//    the machine's, amg beyond.
#include <Eigen/Core>
#include <string>

#include "engine/world.h"
#include "systems/kernels/solver/cg_result.h"
#include "systems/step_term.h"

namespace xcut {

/// Builds the kept preconditioner of the cholesky and amg methods (the factor, the hierarchy) at
/// load, from A at the initial state and the scene's dt, so that the first step does not pay it: a
/// 53k-tet block's hierarchy takes about 250 ms, a stall of the loop a renderer or a haptic device
/// waits on (SOFA builds its solvers' data at init for the same reason). The first step takes it
/// into use as the kept policy says (it renews it if the step's A has another pattern or a larger
/// stiffness weight). Records the time in LinearSystem::load_setup_ms. Nothing for the others.
void prepare_linear_solver(World& world, const StepOperator& op);

/// The method "auto" (or a named method) stands for on this world, and why (for the schedule line).
std::string resolve_linear_method(const World& world, std::string* why = nullptr);

struct LinearSolve {
    CgResult cg;
    bool converged = false;  ///< the relative residual reached the tolerance (false on NaN)
    bool refactored = false; ///< a stale factor was renewed to reach it
};

/// A x = b for the step, A = mass_scale M + stiff_scale (K + K_c): the jacobi method multiplies
/// matrix-free (systems/force_system.h) with diag(A)^-1 from world.forces.stiffness_diagonal; the
/// others assemble A into world.linear first. Every method runs CG as one OpenMP team
/// (systems/kernels/solver/team_cg.h) to |r| <= `limits.tolerance` |b| within `limits.max_iterations`.
/// `x` holds the first guess. A solve above tolerance with a factor older than this step is retried
/// once with a fresh factor.
struct CgLimits {
    double tolerance = 1e-6;   ///< relative residual [-]
    int max_iterations = 200;
};
LinearSolve solve_linear(World& world, const StepOperator& op, double mass_scale, double stiff_scale,
                         const Eigen::VectorXd& b, const Eigen::VectorXd& mask, Eigen::VectorXd& x, const CgLimits& limits);
/// The same at the scene's `solver.cg_tolerance` and `solver.cg_max_iterations`.
inline LinearSolve solve_linear(World& world, const StepOperator& op, double mass_scale, double stiff_scale,
                                const Eigen::VectorXd& b, const Eigen::VectorXd& mask, Eigen::VectorXd& x) {
    return solve_linear(world, op, mass_scale, stiff_scale, b, mask, x,
                        CgLimits{world.solver.cg_tolerance, world.solver.cg_max_iterations});
}

/// A filled for a step by fill_step_matrix.
struct StepMatrix {
    bool assembled = false;    ///< the method assembles A (all but jacobi), and it is filled
};
/// Assembles A = mass_scale M + stiff_scale (K + K_c) into world.linear for the state as it is, if
/// the method assembles it (the pattern first, if the topology changed).
StepMatrix fill_step_matrix(World& world, const StepOperator& op, double mass_scale, double stiff_scale);

/// The step's first solve: as solve_linear at the scene's tolerance and cap, with x's first guess
/// projected from the solutions of the last `solver.guess_history` steps when they were solved for
/// the same system (systems/kernels/solver/projected_guess.h; otherwise x's own guess stands), and this
/// step's solution kept for the next. `filled`: A as fill_step_matrix left it for these scales and
/// this state (it is not filled again), or null.
LinearSolve solve_step_linear(World& world, const StepOperator& op, double mass_scale, double stiff_scale,
                              const Eigen::VectorXd& b, const Eigen::VectorXd& mask, Eigen::VectorXd& x,
                              const StepMatrix* filled = nullptr);

}  // namespace xcut
