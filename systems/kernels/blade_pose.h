#pragma once
// A tool's cutting edge in world coordinates: the tip (deep end) and the heel at a pose.
#include "components/tools.h"

namespace xcut {

/// Tool i's edge at pose k [m].
inline void blade_at(const ToolBodies& tb, int i, const Keyframe& k, Vec3& tip, Vec3& heel) {
    tip = k.position + k.orientation * tb.blade_tip[i];
    heel = k.position + k.orientation * tb.blade_heel[i];
}

/// Tool i's edge at its current pose [m].
inline void blade_in_world(const ToolBodies& tb, int i, Vec3& tip, Vec3& heel) {
    tip = tb.position[i] + tb.orientation[i] * tb.blade_tip[i];
    heel = tb.position[i] + tb.orientation[i] * tb.blade_heel[i];
}

}  // namespace xcut
