#include "systems/solver/energy_check.h"

#include <algorithm>
#include <cmath>

#include "engine/parallel.h"
#include "engine/tool_work.h"

namespace xcut {

StepEnergy motion_energy(const World& world, const Eigen::VectorXd& m3, const Eigen::VectorXd& v) {
    const Nodes& nodes = world.nodes;
    StepEnergy e;
    e.kinetic = 0.5 * deterministic_sum(static_cast<int>(v.size()), [&](int i) { return m3[i] * v[i] * v[i]; });
    e.gravity = -deterministic_sum(nodes.count(), [&](int i) { return nodes.mass[i] * world.gravity.dot(nodes.position[i]); });
    return e;
}

bool gained_energy(const World& world, double h, const StepEnergy& before, const StepEnergy& after) {
    const double work = tool_work(world) * (h / world.solver.dt);
    const double scale = before.kinetic + std::abs(before.stored) + work + std::abs(after.gravity - before.gravity);
    return after.total() - before.total() > work + kEnergyGainTolerance * scale + kEnergyGainFloor;
}

}  // namespace xcut
