#pragma once
// Pure geometry of a cut element (rest configuration): which edges the cut crosses, where, and the
// exact volume of each side (polyhedron volumes, not sampling).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <cstdint>

#include "components/cut_elements.h"

namespace xcut {

inline double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

/// Point on local edge k at parameter t from its first node.
inline Vec3 edge_point(const std::array<Vec3, 4>& X, int dim, int k, double t) {
    const int* e = dim == 3 ? kTetEdges[k] : kTriEdges[k];
    return X[e[0]] + t * (X[e[1]] - X[e[0]]);
}

/// Unit normal of a planar cut through an element from its n points (rest configuration): the
/// largest cross product of two chords from the first point; 2D (the xy plane): the first chord
/// turned by 90 degrees. Zero for fewer than two points, or points that span no plane.
inline Vec3 chord_normal(const Vec3* p, int n, int dim) {
    Vec3 best = Vec3::Zero();
    if (dim == 2 && n >= 2) best = Vec3(p[0].y() - p[1].y(), p[1].x() - p[0].x(), 0.0);
    for (int a = 1; dim == 3 && a < n; ++a)
        for (int b = a + 1; b < n; ++b) {
            const Vec3 v = (p[a] - p[0]).cross(p[b] - p[0]);
            if (v.squaredNorm() > best.squaredNorm()) best = v;
        }
    return best.squaredNorm() > 0.0 ? Vec3(best.normalized()) : Vec3::Zero();
}

/// Volume of the part of a tetrahedron on the side of sign `s`, given node signs H and the crossing
/// parameter of every crossed edge (an edge is crossed iff its end signs differ).
/// One node alone on its side: the corner tetrahedron (node, three edge points).
/// Two and two: the wedge between triangles (A, p_AC, p_AD) and (B, p_BC, p_BD), split into three
/// tetrahedra; its cut face is then the quad split along (p_AD, p_BC), which is what the visual cut
/// face uses too, so volume and picture agree even when the four points are not coplanar.
double tet_side_volume(const std::array<Vec3, 4>& X, const std::array<int8_t, 4>& H, const std::array<double, 6>& t,
                       int side);
/// 2D: area x thickness-free fraction: area of the triangle part on side `side` [m^2].
double tri_side_area(const std::array<Vec3, 4>& X, const std::array<int8_t, 4>& H, const std::array<double, 6>& t,
                     int side);

}  // namespace xcut
