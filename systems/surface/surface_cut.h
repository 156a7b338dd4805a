#pragma once
// Cutting a bound surface along split elements (paper §3.4, Fig. 6). Each mesh element owns the
// pieces it shows (SurfaceMesh::pieces_of), regenerated from its base (skin) triangles when a cut
// touches it:
//  - a cut element's skin triangles crossed by the cut are subdivided, each side keeping its part,
//    and the wound is closed by the internal mesh: the element's edge intersection points and the
//    skin's crossing points on its faces joined into a fan, one copy per side, oriented outward;
//  - a whole element's skin triangles are split at the crack-front points on its edges, so the
//    surface has no T-junction where the incision ends.
// A point on a mesh edge is one vertex for both sides while a whole element still holds that edge
// (the crack front: the lips meet there), and becomes two once every element around the edge is
// cut. Points are made once and reused by every piece that meets them (SurfaceMesh::cut_point), so
// an incision, partial or through, leaves closed 2-manifolds.
#include <array>
#include <vector>

#include "engine/world.h"

namespace xcut {

/// The cut through cut element c, in its rest shape: the plane through its edge points
/// (n . (X - p0) = 0; the largest normal of any three points) and each node's level phi along n,
/// with orient = +1 if positive phi is the H = +1 side, else -1.
struct CutPlaneInfo {
    std::vector<Vec3> points;     ///< edge intersection points, rest [m]
    std::vector<int> point_edge;  ///< their local edges
    Vec3 origin = Vec3::Zero(), normal = Vec3::Zero();
    std::array<double, 4> phi{};
    double orient = 1.0;
};
CutPlaneInfo cut_plane_info(const World& world, int cut);
/// The side (+1 / -1, the H of eq. 9) of the point at barycentric b of cut element e: a point at a
/// node takes that node's H, any other the sign of its level.
int side_of_cut(const World& world, const CutPlaneInfo& cp, int e, const Eigen::Vector4d& b);

/// Key of a rest position for SurfaceMesh::cut_point and base_vertex_at: points closer than 1e-11 m
/// are one place.
std::array<int64_t, 3> surface_place(const Vec3& rest);

/// Triangles of `surface` with no area: twice the area below 1e-12 of the longest edge squared (a
/// height under 2e-12 of the longest edge: zero up to the round-off of positions bound in different
/// elements), at the current positions, as drawn. A cut at 1e-9 of an edge from a node leaves real
/// triangles 1e-9 of an edge high: those have area. None is emitted (the stress suite counts them).
int zero_area_triangles(const SurfaceMesh& surface);

/// Binds the vertices bound to cut element c's mesh element (c having lines, 2D) to the fragment
/// each lies in (systems/surface/surface_fragments.cpp).
void bind_to_fragments(World& world, SurfaceMesh& surface, int c);

/// Regenerates the pieces of the elements cut by cuts [first_cut, world.cuts.count()) and of the
/// elements around their crossed edges, and around the edges of CutElements::crossed_log from
/// first_crossing on (a progressive front's edges crossed after their split), and of the elements
/// cut again (CutElements::recut_log from first_recut on) and those around them. Vertex bindings of
/// the base surface are not touched here.
void cut_surface(World& world, SurfaceMesh& surface, int first_cut, int first_crossing, int first_recut);

}  // namespace xcut
