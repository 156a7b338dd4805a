#pragma once
// Cutting the visual surface along a split element (paper §3.4, Fig. 6): the element's skin
// triangles crossed by the cut are subdivided, each side keeping its part, and the wound is closed
// by the internal mesh: the element's edge intersection points (and the skin's crossing points on
// its faces) joined into a fan, one copy per side, oriented outward. A point is made once per side
// and reused by every element and triangle that meets it (SurfaceMesh::cut_point), so neighbouring
// pieces share vertices and each side's surface stays connected.
// At a crack front (an edge held by the front rule) the two sides' cut faces are not yet joined.
#include <array>
#include <vector>

#include "engine/world.h"

namespace xcut {

/// The cut through cut element c, in its rest shape: the plane through its edge points
/// (n . (X - p0) = 0; Newell's normal for four points) and each node's level phi along n, with
/// orient = +1 if positive phi is the H = +1 side, else -1.
struct CutPlaneInfo {
    std::vector<Vec3> points;     ///< edge intersection points, rest [m]
    std::vector<int> point_edge;  ///< their local edges
    Vec3 origin = Vec3::Zero(), normal = Vec3::Zero();
    std::array<double, 4> phi{};
    double orient = 1.0;
};
CutPlaneInfo cut_plane_info(const World& world, int cut);

/// Subdivides the skin triangles of cut element `cut` and adds its cut faces (3D), or splits its
/// triangles (2D, where the surface is the mesh itself and the gap is the incision).
void cut_surface(World& world, int cut);

}  // namespace xcut
