#pragma once
// Conforming subdivision of a simplex along points on its edges, for the snapping-and-subdivision
// cutter (systems/cut/snap_cut_system.h). Pure functions on node ids: no world, no geometry.
//
// The split is made by bisecting the marked edges one after another in a global order (the order of
// the mesh edge they lie on), each bisection replacing every current piece that holds the edge by
// its two halves. For a tetrahedron crossed by a plane this gives the standard patterns: 3 crossed
// edges (one node alone) -> the corner tetrahedron and 3 tetrahedra for the prism; 4 crossed edges
// (two and two) -> 3 + 3 tetrahedra, the cut quad split along one diagonal; a triangle with 2
// crossed edges -> 1 + 2 triangles. Because the order is global, two elements sharing a face split
// that face into the same triangles, so the mesh stays conforming whatever subset of a face's edges
// carries points (a whole neighbour of a split element is bisected on the shared edges only).
// A half keeps the orientation of its piece (a point on segment ab replaces a or b in place).
#include <array>
#include <cstdint>
#include <vector>

namespace xcut {

/// A point on local edge `edge` of the simplex, node id `node`, bisected in increasing `order`.
struct EdgeSplit {
    int edge = -1;
    int node = -1;
    uint64_t order = 0;
};

/// Pieces of the simplex `nodes` (4 ids; a triangle has nodes[3] = -1, `dim` 2) after bisecting the
/// edges in `splits`. Each piece lists node ids: the simplex's own and the split points.
std::vector<std::array<int, 4>> bisect_simplex(const std::array<int, 4>& nodes, int dim, std::vector<EdgeSplit> splits);

}  // namespace xcut
