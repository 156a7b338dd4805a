#pragma once
// A tool's cutting edge in world coordinates: the tip (deep end) and the heel at a pose; its face.
#include "components/tools.h"

namespace xcut {

/// Tool i's edge at pose k [m].
inline void blade_at(const ToolBodies& tb, int i, const Keyframe& k, Vec3& tip, Vec3& heel) {
    tip = k.position + k.orientation * tb.blade_tip[i];
    heel = k.position + k.orientation * tb.blade_heel[i];
}

/// Tool i's face (from its edge to its back) turned by the pose's orientation R [m]; zero when the
/// blade is an edge only (ToolBodies::blade_back).
inline Vec3 blade_back_at(const ToolBodies& tb, int i, const Eigen::Quaterniond& R) {
    return i < static_cast<int>(tb.blade_back.size()) && tb.blade_back[i] != Vec3::Zero() ? Vec3(R * tb.blade_back[i])
                                                                                           : Vec3::Zero();
}

/// Tool i's edge at its current pose [m].
inline void blade_in_world(const ToolBodies& tb, int i, Vec3& tip, Vec3& heel) {
    tip = tb.position[i] + tb.orientation[i] * tb.blade_tip[i];
    heel = tb.position[i] + tb.orientation[i] * tb.blade_heel[i];
}

}  // namespace xcut
