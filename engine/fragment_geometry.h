#pragma once
// Fragments of a triangle crossed by several cut lines (2D, the xy plane, rest configuration): the
// triangle clipped by one half-plane per line (Sutherland & Hodgman 1974, "Reentrant polygon
// clipping", CACM 17(1): a convex polygon stays convex, vertex by vertex against each line), its
// area (the shoelace formula), and the part of a segment it holds (Cyrus & Beck 1978, "Generalized
// two- and three-dimensional clipping"). docs/xfem.md, Several cuts per element.
#include <array>
#include <cstdint>
#include <vector>

#include "components/cut_elements.h"

namespace xcut {

/// A fragment's mask (VirtualElements::mask): bit k its side of line k, bit kBoundBit + k set when
/// line k bounds it (a line that ends at an earlier one bounds only the fragments it crossed).
inline constexpr int kBoundBit = 16;
inline constexpr uint32_t bound_by(int k) { return 1u << (kBoundBit + k); }

/// Whether rest point x lies on the side of line l that bit value `bit` names (a point on the
/// line lies on both).
inline bool on_side(const CutLine& l, const Vec3& x, bool bit) {
    const double d = l.normal.dot(x - l.origin);
    return bit ? d >= 0.0 : d <= 0.0;
}

/// Whether rest point x lies in the fragment of lines[0..n) that `mask` names (on or inside it).
inline bool in_fragment(const CutLine* lines, int n, uint32_t mask, const Vec3& x) {
    for (int k = 0; k < n; ++k)
        if ((mask & bound_by(k)) && !on_side(lines[k], x, mask >> k & 1u)) return false;
    return true;
}

/// The convex polygon `poly` (xy) clipped to the side of l that `bit` names.
std::vector<Vec3> clip_to_side(const std::vector<Vec3>& poly, const CutLine& l, bool bit);
/// The same for poly[0..n) written to out (room for `room` vertices; std::length_error if the
/// polygon would outgrow it; a convex one gains at most one vertex): returns its vertex count.
int clip_to_side(const Vec3* poly, int n, const CutLine& l, bool bit, Vec3* out, int room);

/// Barycentric coordinates of point x in triangle X (xy).
inline Vec3 triangle_barycentric(const std::array<Vec3, 3>& X, const Vec3& x) {
    const Vec3 u = X[1] - X[0], v = X[2] - X[0], d = x - X[0];
    const double twice = u.x() * v.y() - u.y() * v.x();
    const double b1 = (d.x() * v.y() - d.y() * v.x()) / twice, b2 = (u.x() * d.y() - u.y() * d.x()) / twice;
    return {1.0 - b1 - b2, b1, b2};
}

/// Area of a simple polygon in the xy plane, whatever its orientation [m^2].
double polygon_area(const std::vector<Vec3>& poly);

/// The fragment of triangle (a, b, c) on the sides of lines[0..n) that `mask` names (bit k: line
/// k's side, for each line that bounds it).
std::vector<Vec3> fragment_polygon(const std::array<Vec3, 3>& tri, const CutLine* lines, int n, uint32_t mask);

/// The part [s0, s1] of segment a -> b (parameters from a) on the sides of lines[0..n) that
/// `mask` names (the lines that bound it): s1 <= s0 if it holds none (or a point).
std::array<double, 2> segment_part(const Vec3& a, const Vec3& b, const CutLine* lines, int n, uint32_t mask);

/// The part [s0, s1] of segment a -> b inside the convex polygon `poly` (xy, either orientation):
/// s1 <= s0 if it misses it.
std::array<double, 2> segment_in_polygon(const Vec3& a, const Vec3& b, const std::vector<Vec3>& poly);

}  // namespace xcut

namespace xcut {

// --- 3D: a tetrahedron crossed by several cut planes (CutLine as a plane: a point and its unit
// normal). A fragment is the tetrahedron's intersection with one half-space per plane that bounds
// it, a convex polyhedron; its faces are convex polygons clipped as above, plane by plane, and its
// volume is the divergence theorem's sum over them (V = 1/3 sum_f A_f n_f . (p_f - o)).

/// A face of a convex fragment: its polygon (counter-clockwise seen from outside) and its outward
/// unit normal; `plane` is the cut plane it lies on (k >= 0), or -1 - a for the tetrahedron's face
/// opposite corner a.
struct FragmentFace {
    std::vector<Vec3> polygon;
    Vec3 normal = Vec3::Zero();
    int plane = -1;
};

/// Area of a planar polygon in space [m^2] (Newell's normal, half its length).
double polygon_area_3d(const std::vector<Vec3>& poly);
double polygon_area_3d(const Vec3* poly, int count);

/// The faces of the fragment of tetrahedron X on the sides of planes[0..n) that `mask` names
/// (bit k: plane k's side, for each plane that bounds it); faces of no area are left out.
std::vector<FragmentFace> fragment_faces(const std::array<Vec3, 4>& X, const CutLine* planes, int n, uint32_t mask);

/// Barycentric coordinates of point x in tetrahedron X.
Eigen::Vector4d tet_barycentric(const std::array<Vec3, 4>& X, const Vec3& x);

/// Volume of the convex polyhedron bounded by `faces` [m^3].
double polyhedron_volume(const std::vector<FragmentFace>& faces);

/// polyhedron_volume(fragment_faces(X, planes, n, mask)), the same bits, without allocating [m^3]
/// (a cut again divides each fragment of its element: two volumes each).
double fragment_volume(const std::array<Vec3, 4>& X, const CutLine* planes, int n, uint32_t mask);

/// The part of convex polygon `poly` on the sides of planes (lines) [0..n) that `mask` names: the
/// polygon clipped by each one that bounds it.
std::vector<Vec3> clip_by_planes(std::vector<Vec3> poly, const CutLine* planes, int n, uint32_t mask);

}  // namespace xcut
