#pragma once
// Tool bodies: a pose driven by a scripted trajectory (keyframes: linear position, slerp orientation)
// or by a recorded one replayed from CSV, and for a scalpel the blade's cutting edge in the tool
// frame. Collision geometry (FCL) arrives with the collision issue.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct Keyframe {
    double time = 0.0;                                          ///< [s]
    Vec3 position = Vec3::Zero();                               ///< tool origin in world [m]
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< tool frame -> world
};

struct ToolBodies {
    std::vector<std::string> name;
    std::vector<std::vector<Keyframe>> trajectory;  ///< strictly increasing times
    std::vector<Vec3> position;                     ///< current pose [m]
    std::vector<Eigen::Quaterniond> orientation;
    std::vector<uint8_t> has_blade;
    std::vector<Vec3> blade_tip;                    ///< cutting edge, tool frame: deep end [m]
    std::vector<Vec3> blade_heel;                   ///< cutting edge, tool frame: shallow end [m]

    int count() const { return static_cast<int>(name.size()); }
};

/// Pose at time t: clamped to the first/last keyframe outside the trajectory.
Keyframe sample_trajectory(const std::vector<Keyframe>& keys, double t);

}  // namespace xcut
