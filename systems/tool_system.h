#pragma once
// ToolSystem: moves every tool to its pose at the end of the step (t + dt), from its device (a
// scripted trajectory, a replayed session or a haptic device: engine/devices/device.h), and sets its
// velocity over the step. A bladed tool's motion within the step is sampled too (ToolBodies::sweep):
// the device is asked for the pose half-way between two samples whose blades are farther apart than
// the cut threshold, recursively, so a blade that crosses the body within one step (the first step,
// a long one) is swept whole. Motion that leaves and returns to the same pose between two samples
// is not seen.
#include <functional>

#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// At most this many samples of one tool's sweep per step: beyond it, sweep segments are longer
/// than the threshold (the CutSystem still cuts them, with a deeper search).
constexpr int kMaxSweepSamples = 4097;
/// The pose of tool `i` at time t.
using ToolPoseSource = std::function<Keyframe(int tool, double t)>;
void advance_tools(World& world, double t, const ToolPoseSource& source);
/// From the tools' own trajectories.
void advance_tools(World& world, double t);

SystemDesc tool_system(ToolPoseSource source);

}  // namespace xcut
