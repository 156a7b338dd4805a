#pragma once
// A tool's cutting edge in world coordinates: the tip (deep end) and the heel at a pose; its face.
#include "components/tools.h"
#include "systems/kernels/segment_distance.h"

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

/// A blade that turns within a quad's threshold: its sweep is sampled and a quad ends where the
/// edge strays more than this fraction of the threshold from the straight sweep since the last
/// quad (else the quad cuts the chord across the turn and the elements at its apex stay whole).
inline constexpr double kTurnFraction = 0.1;

/// Whether the edge (tip, heel) lies farther than `tolerance` from the straight sweep of the edge
/// from (tip_a, heel_a) to (tip_b, heel_b): either end off its chord [m]. A blade that turned there.
inline bool edge_off_sweep(const Vec3& tip, const Vec3& heel, const Vec3& tip_a, const Vec3& heel_a, const Vec3& tip_b,
                           const Vec3& heel_b, double tolerance) {
    return segment_distance(tip, tip_a, tip_b) > tolerance || segment_distance(heel, heel_a, heel_b) > tolerance;
}

}  // namespace xcut
