#pragma once
// The work the tools did on the tissue over a step, bounded above: what the WatchdogSystem counts
// into the energy put in, and what the step's energy check allows a step to gain
// (systems/solver/energy_check.h).
#include <cmath>

#include "engine/world.h"

namespace xcut {

/// The work the tools' contacts and grasps did on the tissue over the last step, bounded above
/// (|F . v| dt per tool, less the blades' cutting resistance, plus the graspers') [J].
inline double tool_work(const World& w) {
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

}  // namespace xcut
