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
    double kinetic_energy = 0.0;  ///< [J]
    double elastic_energy = 0.0;  ///< [J]
    double gravity_work = 0.0;    ///< work done by gravity since rest, sum m g.(x - X) [J]
    std::vector<double> system_ms;  ///< wall time per scheduled system [ms], schedule order
    double step_ms = 0.0;         ///< wall time of the whole step [ms]
};

struct Metrics {
    std::vector<std::string> system_names;
    StepMetrics current;
};

}  // namespace xcut
