#pragma once
// The rest triangles of a 2D mesh as the crack tips' code takes them (systems/cut/crack_tip_system.cpp,
// crack_tip_display.cpp): a mesh element's corners in the plane, and a point's barycentric
// coordinates in them.
#include <Eigen/LU>
#include <array>

#include "engine/world.h"

namespace xcut {
namespace tip_triangles {

inline Vec2 xy(const Vec3& v) { return v.head<2>(); }

/// Mesh element e's rest corners in the plane [m].
inline std::array<Vec2, 3> rest_triangle(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {xy(w.nodes.rest[n[0]]), xy(w.nodes.rest[n[1]]), xy(w.nodes.rest[n[2]])};
}

/// The barycentric coordinates of point T in triangle X.
inline Vec3 barycentric(const std::array<Vec2, 3>& X, const Vec2& T) {
    Eigen::Matrix2d D;
    D << X[1] - X[0], X[2] - X[0];
    const Vec2 l = D.partialPivLu().solve(T - X[0]);
    return Vec3(1.0 - l.x() - l.y(), l.x(), l.y());
}

}  // namespace tip_triangles
}  // namespace xcut
