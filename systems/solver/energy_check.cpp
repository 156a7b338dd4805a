#include "systems/solver/energy_check.h"

#include <algorithm>
#include <cmath>

#include "engine/parallel.h"

namespace xcut {

StepEnergy motion_energy(const World& world, const Eigen::VectorXd& m3, const Eigen::VectorXd& v) {
    const Nodes& nodes = world.nodes;
    StepEnergy e;
    e.kinetic = 0.5 * deterministic_sum(static_cast<int>(v.size()), [&](int i) { return m3[i] * v[i] * v[i]; });
    e.gravity = -deterministic_sum(nodes.count(), [&](int i) { return nodes.mass[i] * world.gravity.dot(nodes.position[i]); });
    return e;
}

bool gained_energy(const StepEnergy& before, const StepEnergy& after, double work) {
    const double scale = before.kinetic + std::abs(before.stored) + std::abs(work) + std::abs(after.gravity - before.gravity);
    return after.total() - before.total() > work + kEnergyGainTolerance * scale + kEnergyGainFloor;
}

}  // namespace xcut
