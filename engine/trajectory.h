#pragma once
// Sampling a tool's trajectory: what the devices (engine/devices) and the ToolSystem share. The
// engine owns it: a device is the engine's, and it must not reach up into a system to move a tool.
#include <vector>

#include "components/tools.h"

namespace xcut {

/// Pose at time t: clamped to the first/last keyframe outside the trajectory.
Keyframe sample_trajectory(const std::vector<Keyframe>& keys, double t);
/// Pose at time t on the segment a -> b (clamped to its ends): linear position, slerp orientation.
Keyframe interpolate_pose(const Keyframe& a, const Keyframe& b, double t);

}  // namespace xcut
