#pragma once
// Where a 3D surface's wounds touch along a line, the lines' vertices are split so that the surface
// stays a 2-manifold (docs/xfem.md, Several incisions at one place).
//
// Where incisions end beside elements cut again, node copies can give both lips of two neighbouring
// cut elements (or a wound and the skin beside it) one vertex along their trace on a face: each
// element's wound is a lens that closes there, and the two lenses meet along that trace, every edge
// of it in four triangles (closed and oriented, but pinched). After each cut the triangles of an
// edge used more than twice are paired, one each way, those of one element and one kind (skin with
// skin, wound with wound) first; round every vertex of such an edge the triangles joined through
// their pairs make one fan, and each fan after the first takes a copy of the vertex, bound where it
// is bound (so it moves with it). Where those pairs stay joined round both ends by other edges, the
// edge's four triangles are paired the other way and the fans made again. The copies are laid over the surface as the crack tips' opening
// is (systems/surface/surface_tips.h) and taken off before the surface is cut again; contacts and
// grasps act on the vertex a copy was made of, so nothing is pushed or held twice.
#include "engine/world.h"

namespace xcut {

/// Splits the vertices of `surface`'s edges in more than two triangles (3D, XFEM), recording the
/// copies (SurfaceMesh::manifold_first_vertex); nothing in 2D or with the snapping cutter.
void split_pinched_edges(const World& world, SurfaceMesh& surface);

/// Takes the copies off again: the triangles use the vertices they were made with, and a grasp
/// holding a copy holds the vertex it was made of.
void take_off_pinch_split(World& world, SurfaceMesh& surface);

}  // namespace xcut
