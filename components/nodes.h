#pragma once
// Nodes of the simulation mesh: one entry per mesh vertex, fields as separate contiguous arrays
// (structure of arrays) so a system streams only what it reads. Each array is a contiguous run of
// doubles, usable as an Eigen::Map over 3*count() values.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace xcut {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

struct Nodes {
    std::vector<Vec3> rest;       ///< rest positions X [m]
    std::vector<Vec3> position;   ///< current positions x [m]
    std::vector<Vec3> velocity;   ///< velocities v [m/s]
    std::vector<double> mass;     ///< lumped mass [kg]
    std::vector<uint8_t> fixed;   ///< bit k set: axis k is held (velocity projected to zero)

    int count() const { return static_cast<int>(rest.size()); }
};

}  // namespace xcut
