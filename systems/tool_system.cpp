#include "systems/tool_system.h"

#include <algorithm>

namespace xcut {

Keyframe sample_trajectory(const std::vector<Keyframe>& keys, double t) {
    if (keys.empty()) return Keyframe{};
    if (t <= keys.front().time) return keys.front();
    if (t >= keys.back().time) return keys.back();
    const auto hi = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double v, const Keyframe& k) { return v < k.time; });
    const Keyframe& b = *hi;
    const Keyframe& a = *(hi - 1);
    const double s = (t - a.time) / (b.time - a.time);
    Keyframe out;
    out.time = t;
    out.position = (1.0 - s) * a.position + s * b.position;
    out.orientation = a.orientation.slerp(s, b.orientation);
    return out;
}

void blade_in_world(const World& world, int i, Vec3& tip, Vec3& heel) {
    const ToolBodies& tb = world.tools;
    tip = tb.position[i] + tb.orientation[i] * tb.blade_tip[i];
    heel = tb.position[i] + tb.orientation[i] * tb.blade_heel[i];
}

void advance_tools(World& world, double t) {
    advance_tools(world, t, [&world](int i, double s) { return sample_trajectory(world.tools.trajectory[i], s); });
}

void advance_tools(World& world, double t, const ToolPoseSource& source) {
    ToolBodies& tb = world.tools;
    const double dt = t - world.time;
    tb.velocity.resize(tb.count(), Vec3::Zero());
    for (int i = 0; i < tb.count(); ++i) {
        const Keyframe k = source(i, t);
        tb.velocity[i] = dt > 0.0 ? Vec3((k.position - tb.position[i]) / dt) : Vec3::Zero();
        tb.position[i] = k.position;
        tb.orientation[i] = k.orientation;
    }
}

SystemDesc tool_system(ToolPoseSource source) {
    return {"ToolSystem", kTools, kTools, [source](World& w) { advance_tools(w, w.time + w.solver.dt, source); }};
}

}  // namespace xcut
