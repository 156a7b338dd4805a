#pragma once
// SolverSystem: one implicit (backward) Euler step, linearized once (Baraff & Witkin 1998), with
// Rayleigh damping D = alpha M + beta K and the rotations frozen (corotational, paper §4.3):
//
//   [(1 + h alpha) M + (h^2 + h beta) K] dv = h f - (h^2 + h beta) K v - h alpha M v,
//   v <- v + dv,  x <- x + h v.
//
// The system is solved by the linear-solver stage (systems/solver/linear_solver.h: matrix-free Jacobi CG,
// or the assembled matrix with a block-Jacobi or Cholesky-preconditioned CG, per solver.linear).
// Held axes are removed by projecting residual and search direction (the filter of Baraff &
// Witkin), so constraints add no stiffness and the system stays SPD. CG starts from the previous
// step's dv; its dot products are summed in a fixed order, so a step is bit-identical for any
// thread count.
//
// No silent failure: a solve above its tolerance (or NaN) is not accepted. The stage renews a
// stale factor first; then the step is redone in 2, 4, ... solver.max_substeps substeps; then the
// run stops with a NumericalError naming the step, the residual and what to change. The metrics
// carry each step's residual, solve_flag (0, 1 renewed factor, 2 substeps) and substep count.
#include <Eigen/Core>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/kernels/solver/cg_result.h"
#include "systems/step_term.h"

namespace xcut {

/// Applies the constraint filter: zero the velocity of held axes.
void project_constraints(const World& world, Eigen::Ref<Eigen::VectorXd> v);

/// One step of the scene's dt with the step's terms (systems/step_term.h).
void implicit_euler_step(World& world, const StepOperator& op);

struct StaticResult {
    int newton_iterations = 0;
    int cg_iterations = 0;         ///< summed over the Newton iterations
    double residual = 0.0;         ///< |f_free| / |f_free at start| reached
    bool converged = false;
    bool at_round_off = false;     ///< converged by a negligible update, the residual above tolerance
};
/// Static equilibrium f(x) = 0 on the free axes: Newton iterations with the corotational stiffness
/// (rotations refreshed per iteration), each K dx = f solved by the scene's linear method
/// (`solver.linear`, systems/solver/linear_solver.h) to `cg_tolerance` within `cg_max_iterations`. For
/// verification problems (patch test, cantilever); velocities are left untouched. `load`: external
/// nodal forces [N], 3 per DOF node (a traction spread on boundary nodes), or empty.
StaticResult static_solve(World& world, const StepOperator& op, double tolerance, int max_newton, double cg_tolerance,
                          int cg_max_iterations, const Eigen::VectorXd& load = Eigen::VectorXd());
/// The SolverSystem over the step's terms, handed in by the pipeline (it names none of their
/// systems); its schedule line says which linear method runs and why.
SystemDesc solver_system(const World& world, std::shared_ptr<const StepOperator> op);

}  // namespace xcut

