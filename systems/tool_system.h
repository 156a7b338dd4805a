#pragma once
// ToolSystem: moves every tool to its pose at the end of the step (t + dt), from its device (a
// scripted trajectory, a replayed session or a haptic device: engine/devices/device.h), and sets its
// velocity over the step.
#include <functional>

#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// World-space cutting edge of tool `i`: tip (deep end) and heel.
void blade_in_world(const World& world, int tool, Vec3& tip, Vec3& heel);
/// The pose of tool `i` at time t.
using ToolPoseSource = std::function<Keyframe(int tool, double t)>;
void advance_tools(World& world, double t, const ToolPoseSource& source);
/// From the tools' own trajectories.
void advance_tools(World& world, double t);

SystemDesc tool_system(ToolPoseSource source);

}  // namespace xcut
