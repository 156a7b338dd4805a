#pragma once
// ToolSystem: moves every tool to its trajectory's pose at the end of the step (t + dt).
#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// World-space cutting edge of tool `i`: tip (deep end) and heel.
void blade_in_world(const World& world, int tool, Vec3& tip, Vec3& heel);
void advance_tools(World& world, double t);

SystemDesc tool_system();

}  // namespace xcut
