#pragma once
// Distance from a point to a segment, in the plane (2D meshes, the tip's polygon) or in space (the
// blade's sweep).
#include <algorithm>

namespace xcut {

/// Distance from p to the segment a-b, for Eigen vectors of any fixed size [m]; a segment of zero
/// length is its end a.
template <class V>
double segment_distance(const V& p, const V& a, const V& b) {
    const V e = b - a;
    const double len2 = e.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(e) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + t * e)).norm();
}

}  // namespace xcut
