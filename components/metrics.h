#pragma once
// Per-step figures, one row per step in the metrics CSV.
#include <string>
#include <vector>

namespace xcut {

struct StepMetrics {
    int step = 0;
    double time = 0.0;            ///< simulated time at the end of the step [s]
    double dt = 0.0;              ///< [s]
    int dofs = 0;                 ///< free scalar degrees of freedom
    int cg_iterations = 0;                 ///< summed over the step's Newton iterations
    int newton_iterations = 1;
    double cg_residual = 0.0;     ///< relative residual reached
    /// How the step's solve was accepted: 0 at once, 1 after renewing the factor, 2 in substeps.
    int solve_flag = 0;
    int substeps = 1;             ///< substeps the step took (a power of 2)
    /// The kept preconditioner in this step (cholesky, amg; components/linear_system.h): 0 kept as it
    /// is, 1 aged while a renewed one is built off the step, 2 a renewed one taken into use, 3 built
    /// in the step.
    int preconditioner = 0;
    double preconditioner_wait_ms = 0.0;  ///< the step waited for the one built off the step [ms]
    double kinetic_energy = 0.0;  ///< [J]
    double elastic_energy = 0.0;  ///< [J]
    double gravity_work = 0.0;    ///< work done by gravity since rest, sum m g.(x - X) [J]
    std::vector<double> system_ms;  ///< wall time per scheduled system [ms], schedule order
    double step_ms = 0.0;         ///< wall time of the whole step [ms]
};

struct Metrics {
    std::vector<std::string> system_names;
    StepMetrics current;
    int refactored_steps = 0;     ///< steps whose solve needed a renewed factor
    int substepped_steps = 0;     ///< steps split into substeps to converge
    int max_substeps = 1;         ///< the most substeps one step took
    /// once-linearized steps (or substeps) that gained energy and were iterated by Newton
    int energy_newton_steps = 0;
    double work_in = 0.0;         ///< energy put in so far: first energy, gravity, tools [J] (watchdog)
};

}  // namespace xcut
