#pragma once
// Kinematic constraints, applied by projection in the solver: a held node keeps its velocity on the
// held axes at zero (Baraff & Witkin's filter), so no penalty stiffness enters the system.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace xcut {

struct FixedBox {
    Eigen::Vector3d min;   ///< [m]
    Eigen::Vector3d max;   ///< [m]
    uint8_t axes = 7;      ///< bit mask of held axes (x=1, y=2, z=4)
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  ///< held nodes start displaced by this [m]
};

/// A node set held like a box, named in the scene by a region of a body's mesh, a sphere or an index
/// file, and resolved to node indices when the world is built.
struct FixedSet {
    std::vector<int> nodes;
    uint8_t axes = 7;      ///< bit mask of held axes (x=1, y=2, z=4)
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  ///< held nodes start displaced by this [m]
};

struct Constraints {
    std::vector<FixedBox> boxes;
    std::vector<FixedSet> sets;
    std::vector<int> nodes;            ///< explicitly fixed node indices (all axes)
};

}  // namespace xcut
