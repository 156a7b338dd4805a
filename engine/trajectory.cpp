#include "engine/trajectory.h"

#include <algorithm>

namespace xcut {

Keyframe sample_trajectory(const std::vector<Keyframe>& keys, double t) {
    if (keys.empty()) return Keyframe{};
    if (t <= keys.front().time) return keys.front();
    if (t >= keys.back().time) return keys.back();
    const auto hi = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double v, const Keyframe& k) { return v < k.time; });
    return interpolate_pose(*(hi - 1), *hi, t);
}

Keyframe interpolate_pose(const Keyframe& a, const Keyframe& b, double t) {
    Keyframe out = t <= a.time ? a : b;
    out.time = t;
    if (t <= a.time || t >= b.time || !(b.time > a.time)) return out;
    const double s = (t - a.time) / (b.time - a.time);
    out.position = (1.0 - s) * a.position + s * b.position;
    out.orientation = a.orientation.slerp(s, b.orientation);
    return out;
}

}  // namespace xcut
