#pragma once
// "tools[i].grasp" (docs/scene-format.md, Graspers): when a tool's jaws close and open, their reach
// and the stiffness that holds the skin. Internal to engine/io.
#include "components/grasps.h"
#include "engine/io/json_fields.h"

namespace xcut {

/// Appends tool t's grasp settings to `grasps` (radius 0 without "grasp"); an InputError naming the
/// field for a bad value.
void read_tool_grasp(const JsonFields& tool, Grasps& grasps);

}  // namespace xcut
