#pragma once
// The volume mesh as ParaView should show it: every uncut element as it is, and each virtual
// element clipped to its own side of the cut, so the wound opens instead of two full-size tets
// overlapping. A side of a cut tetrahedron is a tetrahedron (one node on that side) or a triangular
// prism (two or three nodes), written as 1 or 3 tetrahedra; in 2D a triangle or a quadrilateral
// (1 or 2 triangles). The cut points are the edge crossings the CutElements keep (rest frame), placed
// by the virtual element's own nodes (real or phantom): the piece moves with its side (paper §3.2).
// A quadratic element (systems/kernels/quadratic_tet.h), cut or not, gives quadratic tetrahedra
// (VTK cell type 24): a piece's corners and mid-edge points are placed by its element's (or its
// side's) 10 shape functions, so a bent cut element is drawn as it deforms and its pieces meet their
// neighbours' curved faces (a quadratic field on a sub-tetrahedron is its own quadratic interpolant).
#include <array>
#include <vector>

#include "engine/world.h"

namespace xcut {

struct ClippedCells {
    std::vector<Vec3> position;      ///< the world's nodes, then one point per cut point of each piece [m]
    std::vector<Vec3> rest;          ///< rest positions of the same [m]
    std::vector<Vec3> velocity;      ///< [m/s]; a cut point's is interpolated along its edge
    std::vector<std::array<int, 4>> cells;  ///< tetrahedra (2D: triangles, [3] = -1), positively oriented
    std::vector<int> element;        ///< the force element (mesh or virtual) each cell shows
    /// per cell: its index in edge_points if it is quadratic (a 10-node tetrahedron, 2D a 6-node
    /// triangle), -1 if it is linear
    std::vector<int> quadratic;
    std::vector<std::array<int, 6>> edge_points;  ///< a quadratic cell's mid-edge points (kTet10Edges order; a triangle's first 3)
};

/// Every element carrying material (weight > 0), virtual ones clipped to their side. A virtual
/// element whose cut has fewer points than a full crossing is written whole.
ClippedCells clipped_cells(const World& world);

}  // namespace xcut
