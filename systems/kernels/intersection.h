#pragma once
// Exact-enough double-precision predicates for the cut: does a mesh edge cross the blade's swept
// surface, and where. Embree (single precision) only proposes candidate elements; these decide.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
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
/// With the ends' orientations o0 = orient3d(a, b, c, p0) and o1 = orient3d(a, b, c, p1) given (a
/// caller testing many edges against one triangle computes each node's once).
inline std::optional<double> segment_triangle(double o0, double o1, const Vec3& p0, const Vec3& p1, const Vec3& a,
                                              const Vec3& b, const Vec3& c) {
    if ((o0 > 0 && o1 > 0) || (o0 < 0 && o1 < 0) || o0 == o1) return std::nullopt;
    const double s0 = orient3d(p0, p1, a, b), s1 = orient3d(p0, p1, b, c), s2 = orient3d(p0, p1, c, a);
    const bool inside = (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
    if (!inside) return std::nullopt;
    return std::clamp(o0 / (o0 - o1), 0.0, 1.0);
}

inline std::optional<double> segment_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b,
                                              const Vec3& c) {
    return segment_triangle(orient3d(a, b, c, p0), orient3d(a, b, c, p1), p0, p1, a, b, c);
}

/// The root in [0, 1] of the quadratic g(s) through g(0) = g0, g(1/2) = gm, g(1) = g1 (a quadratic
/// element's edge, s its parameter: g = g0 (1 - s)(1 - 2s) + gm 4 s (1 - s) + g1 s (2s - 1)), for
/// g0 and g1 of opposite signs or one of them zero: then exactly one root lies in [0, 1]. The
/// smaller-cancellation form of the quadratic formula (Press et al., Numerical Recipes, §5.6).
inline double quadratic_edge_root(double g0, double gm, double g1) {
    const double A = 2.0 * g0 + 2.0 * g1 - 4.0 * gm, B = 4.0 * gm - 3.0 * g0 - g1, C = g0;
    const double linear = g0 != g1 ? std::clamp(g0 / (g0 - g1), 0.0, 1.0) : 0.5;
    if (A == 0.0) return B != 0.0 ? std::clamp(-C / B, 0.0, 1.0) : linear;
    const double disc = std::max(0.0, B * B - 4.0 * A * C);
    const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    double best = linear, best_g = std::numeric_limits<double>::infinity();
    for (double r : {q / A, q != 0.0 ? C / q : -C / B}) {
        if (!(r >= -1e-12 && r <= 1.0 + 1e-12)) continue;
        r = std::clamp(r, 0.0, 1.0);
        const double g = std::abs((A * r + B) * r + C);
        if (g < best_g) best = r, best_g = g;
    }
    return best;
}

/// The point at parameter s of the quadratic edge through p0 (s = 0), pm (1/2) and p1 (1).
inline Vec3 quadratic_edge_point(const Vec3& p0, const Vec3& pm, const Vec3& p1, double s) {
    return (1.0 - s) * (1.0 - 2.0 * s) * p0 + 4.0 * s * (1.0 - s) * pm + s * (2.0 * s - 1.0) * p1;
}

/// The quadratic edge p0-pm-p1 against triangle abc, as segment_triangle for a straight one: the
/// parameter s of the crossing, or nothing. Its ends on opposite sides of the triangle's plane (or
/// one on it), and the point where the curve meets the plane inside the triangle (its boundary
/// counts). A curved edge whose ends lie on one side crosses the plane twice or not at all: not
/// counted, as a straight edge's.
inline std::optional<double> quadratic_edge_triangle(const Vec3& p0, const Vec3& pm, const Vec3& p1, const Vec3& a,
                                                     const Vec3& b, const Vec3& c) {
    const double o0 = orient3d(a, b, c, p0), o1 = orient3d(a, b, c, p1);
    if ((o0 > 0 && o1 > 0) || (o0 < 0 && o1 < 0) || o0 == o1) return std::nullopt;
    const double s = quadratic_edge_root(o0, orient3d(a, b, c, pm), o1);
    const Vec3 q = quadratic_edge_point(p0, pm, p1, s);
    const Vec3 d = (4.0 * s - 3.0) * p0 + (4.0 - 8.0 * s) * pm + (4.0 * s - 1.0) * p1;  // the tangent
    const double s0 = d.dot((a - q).cross(b - q)), s1 = d.dot((b - q).cross(c - q)), s2 = d.dot((c - q).cross(a - q));
    const bool inside = (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
    if (!inside) return std::nullopt;
    return s;
}

inline double cross_xy(const Vec3& a, const Vec3& b) { return a.x() * b.y() - a.y() * b.x(); }

/// 2D (xy): segment p0-p1 against segment a-b; t along p0-p1 of the crossing, or nothing.
/// Touching counts; collinear overlap does not cross.
inline std::optional<double> segment_segment_2d(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b) {
    const Vec3 r = p1 - p0, s = b - a;
    const double den = cross_xy(r, s);
    if (den == 0.0) return std::nullopt;
    const double t = cross_xy(a - p0, s) / den, u = cross_xy(a - p0, r) / den;
    if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return std::nullopt;
    return t;
}

}  // namespace xcut
