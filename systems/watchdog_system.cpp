#include "systems/watchdog_system.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "engine/error.h"
#include "engine/parallel.h"

namespace xcut {
namespace {

/// The first node whose position or velocity is not finite, or -1.
int first_non_finite(const Nodes& nodes) {
    const int n = nodes.count();
    const double bad = deterministic_sum(n, [&](int i) {
        return nodes.position[i].allFinite() && nodes.velocity[i].allFinite() ? 0.0 : 1.0;
    });
    if (bad == 0.0) return -1;
    for (int i = 0; i < n; ++i)
        if (!nodes.position[i].allFinite() || !nodes.velocity[i].allFinite()) return i;
    return -1;
}

/// The work the tools' contacts and grasps did on the tissue over the last step, bounded above [J].
double tool_work(const World& w) {
    const ToolBodies& tb = w.tools;
    double work = 0.0;
    for (int i = 0; i < tb.count(); ++i) {
        if (i >= static_cast<int>(tb.reaction_force.size()) || i >= static_cast<int>(tb.velocity.size())) continue;
        // The blades' cutting resistance is spent opening the cut, not on the tissue's energy.
        const Vec3 cutting = i < static_cast<int>(tb.cutting_force.size()) ? tb.cutting_force[i] : Vec3::Zero();
        work += std::abs((tb.reaction_force[i] - cutting).dot(tb.velocity[i])) * w.solver.dt;
    }
    return work + w.grasps.step_work;  // the graspers' (systems/grasp_system.h)
}

}  // namespace

void check_state(World& w) {
    const StepMetrics& m = w.metrics.current;
    if (const int i = first_non_finite(w.nodes); i >= 0)
        throw NumericalError(fmt::format(
            "step {} (t = {:.6g} s): node {} has a NaN or infinite position or velocity (last solve: {} CG iterations, "
            "relative residual {:.3g}). The state is garbage; the run stops. Change: the material (E, nu) or gravity "
            "to physical values, a smaller solver.dt, or solver.newton.iterations for large rotations",
            w.step, w.time, i, m.cg_iterations, m.cg_residual));
    Metrics& metrics = w.metrics;
    const double energy = m.kinetic_energy + m.elastic_energy;
    if (w.step <= 1) metrics.work_in = energy;  // the state's own energy at the start
    metrics.work_in += tool_work(w);
    const double put_in = metrics.work_in + std::max(0.0, m.gravity_work);
    if (!(energy <= w.solver.energy_factor * put_in + 1e-12))
        throw NumericalError(fmt::format(
            "step {} (t = {:.6g} s): kinetic + elastic energy {:.4g} J is more than {} times the energy put in "
            "({:.4g} J: start, gravity, tools): the simulation is diverging. Change: a smaller solver.dt, "
            "solver.newton.iterations > 1 (large rotations), damping, or the material",
            w.step, w.time, energy, w.solver.energy_factor, put_in));
}

SystemDesc watchdog_system() { return {"WatchdogSystem", kNodes | kElements, kMetrics, check_state}; }

}  // namespace xcut
