#pragma once
// Clipping a segment a + s (b - a), s in [s0, s1], to convex cells: half-spaces, tetrahedra, and
// triangles of the xy plane (Cyrus & Beck 1978, "Generalized two- and three-dimensional clipping":
// the parameter interval shrinks plane by plane). Exact in double up to rounding; an interval that
// shrinks to nothing leaves s0 > s1.
#include <array>

#include "components/nodes.h"

namespace xcut {

/// Keeps the part of [s0, s1] where n . (a + s (b - a) - p) >= 0; `open`: > 0, so a segment lying in
/// the plane belongs to one of two complementary half-spaces only.
inline void clip_to_half_space(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& n, double& s0, double& s1,
                               bool open = false) {
    const double at = n.dot(a - p), slope = n.dot(b - a);
    if (slope == 0.0) {
        if (at < 0.0 || (open && at == 0.0)) s0 = 1.0, s1 = 0.0;
        return;
    }
    const double root = -at / slope;
    if (slope > 0.0) s0 = root > s0 ? root : s0;
    else s1 = root < s1 ? root : s1;
}

/// The segment's parameter interval inside tetrahedron x (any orientation): s0 > s1 if none.
inline void clip_to_tet(const std::array<Vec3, 4>& x, const Vec3& a, const Vec3& b, double& s0, double& s1) {
    static constexpr int kFaces[4][4] = {{1, 2, 3, 0}, {0, 2, 3, 1}, {0, 1, 3, 2}, {0, 1, 2, 3}};  // face, opposite
    for (const auto& f : kFaces) {
        Vec3 n = (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
        if (n.dot(x[f[3]] - x[f[0]]) < 0.0) n = -n;  // inward
        clip_to_half_space(a, b, x[f[0]], n, s0, s1);
        if (s0 > s1) return;
    }
}

/// Point p inside triangle x[0..2] of the xy plane (either orientation), boundary included.
inline bool in_triangle_xy(const std::array<Vec3, 4>& x, const Vec3& p) {
    const auto cross = [](const Vec3& o, const Vec3& u, const Vec3& v) {
        return (u.x() - o.x()) * (v.y() - o.y()) - (u.y() - o.y()) * (v.x() - o.x());
    };
    const double d0 = cross(x[0], x[1], p), d1 = cross(x[1], x[2], p), d2 = cross(x[2], x[0], p);
    return (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0);
}

}  // namespace xcut
