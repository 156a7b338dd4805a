#pragma once
// Exact-enough double-precision predicates for the cut: does a mesh edge cross the blade's swept
// surface, and where. Embree (single precision) only proposes candidate elements; these decide.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>

#include "components/nodes.h"

namespace xcut {

/// Six times the signed volume of (a, b, c, d).
inline double orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return (b - a).dot((c - a).cross(d - a));
}

/// Segment p0-p1 against triangle abc. Returns the parameter t in [0, 1] of the crossing along the
/// segment, or nothing. Touching counts (points on the triangle's boundary, an end on the plane), so
/// a crossing on the diagonal shared by a quad's two triangles is found by both; callers keep one
/// per edge. A segment lying in the triangle's plane does not cross it.
inline std::optional<double> segment_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b,
                                              const Vec3& c) {
    const double o0 = orient3d(a, b, c, p0), o1 = orient3d(a, b, c, p1);
    if ((o0 > 0 && o1 > 0) || (o0 < 0 && o1 < 0) || o0 == o1) return std::nullopt;
    const double s0 = orient3d(p0, p1, a, b), s1 = orient3d(p0, p1, b, c), s2 = orient3d(p0, p1, c, a);
    const bool inside = (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
    if (!inside) return std::nullopt;
    return std::clamp(o0 / (o0 - o1), 0.0, 1.0);
}

inline double cross2(const Vec3& a, const Vec3& b) { return a.x() * b.y() - a.y() * b.x(); }

/// 2D (xy): segment p0-p1 against segment a-b; t along p0-p1 of the crossing, or nothing.
/// Touching counts; collinear overlap does not cross.
inline std::optional<double> segment_segment_2d(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b) {
    const Vec3 r = p1 - p0, s = b - a;
    const double den = cross2(r, s);
    if (den == 0.0) return std::nullopt;
    const double t = cross2(a - p0, s) / den, u = cross2(a - p0, r) / den;
    if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return std::nullopt;
    return t;
}

}  // namespace xcut
