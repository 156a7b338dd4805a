#pragma once
// MappingSystem (paper §3.2, §3.4): keeps the visual surface on the simulated body.
//  - After cuts: every vertex bound to an element that was just split is re-bound to the virtual
//    element on its side of the cut, with the same barycentric coordinates (a virtual element has
//    its parent's rest shape and vertex order). Only those vertices are touched (reverse index).
//  - Every step: each vertex's position is interpolated from its element's current vertices, so a
//    vertex on one lip of a wound follows that lip's virtual element (eq. 4, 6).
// Not yet here: subdividing surface triangles the cut crosses and closing the wound with the
// internal cut faces (the next step of the visual-mapping work).
#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// The boundary of the tetrahedral mesh (faces of exactly one tetrahedron), outward, each vertex
/// bound to the tetrahedron owning one of its faces; `subdivisions` times every triangle is split in
/// four (edge midpoints bound to the owning tetrahedron), so the surface is finer than the physics.
void build_visual_surface(World& world, int subdivisions);
/// Re-binds the vertices of newly cut elements; returns how many were re-bound.
int rebind_cut_vertices(World& world);
/// Positions of all surface vertices from the current DOF positions.
void update_surface_positions(World& world);

SystemDesc mapping_system();

}  // namespace xcut
