#pragma once
// MappingSystem (paper §3.2, §3.4): keeps the visual surface on the simulated body.
//  - After cuts: every vertex bound to an element that was just split is re-bound to the virtual
//    element on its side of the cut, with the same barycentric coordinates (a virtual element has
//    its parent's rest shape and vertex order). Only those vertices are touched (reverse index).
//  - Every step: each vertex's position is interpolated from its element's current vertices, so a
//    vertex on one lip of a wound follows that lip's virtual element (eq. 4, 6).
//  - The surface is cut along the new cut elements and closed by their cut faces
//    (systems/surface/surface_cut.h).
// Two surfaces are mapped: the visual one and the collision one (coarser, for tool contact). On a
// quadratic element the visual surface follows the element's quadratic shape functions.
#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/surface/surface_cut.h"
#include "systems/xfem_queries.h"

namespace xcut {

/// The boundary of the tetrahedral mesh (faces of exactly one tetrahedron), outward, each vertex
/// bound to the tetrahedron owning one of its faces; `subdivisions` times every triangle is split in
/// four (edge midpoints bound to the owning tetrahedron), so the surface is finer than the physics.
void build_surface(const World& world, SurfaceMesh& surface, int subdivisions);
void build_visual_surface(World& world, int subdivisions);
/// The force element carrying the point at barycentric `b` of cut element c (a CutElements index;
/// `cp` = cut_plane_info(world, c)): the virtual element of the point's side, as map_cuts binds a
/// surface vertex. `side` gets that side (+1 / -1) when given. Probe points are bound this way.
inline int side_element(const World& w, int c, const CutPlaneInfo& cp, const Eigen::Vector4d& b, int8_t* side = nullptr) {
    const int h = side_of_cut(w, cp, w.cuts.element[c], b);
    if (side) *side = static_cast<int8_t>(h);
    return w.virtual_elements.element[w.cuts.virtual_element[c][h > 0 ? 0 : 1]];
}
/// Maps the cuts made since the last call onto `surface`: re-binds the vertices of newly cut
/// elements and cuts the surface; returns how many vertices were re-bound.
int map_cuts(World& world, SurfaceMesh& surface);
/// map_cuts on the collision surface, then the visual one; returns the visual count.
int rebind_cut_vertices(World& world);
/// Positions of all vertices of `surface` from the current DOF positions. `curved`: a vertex bound to
/// a quadratic element follows its 10 shape functions (systems/kernels/quadratic_tet.h), so a
/// subdivided surface shows the bending its mid-edge nodes carry inside the element; else every
/// vertex follows its element's corners linearly (bound_position). The visual surface is curved; the
/// collision surface is not: a contact's force goes to the corners by the same linear weights that
/// place its vertex (systems/collision_system.h), so the two stay work-conjugate.
void update_surface_positions(const World& world, SurfaceMesh& surface, bool curved = false);
/// Both surfaces (the visual one curved).
void update_surface_positions(World& world);

/// The RebindSystem: before the CollisionSystem, the collision surface follows this step's splits
/// (its vertices re-bound to the virtual elements on their side) and positions, so the contacts are
/// found on the tissue as it is and their forces land on the right lip. It runs when the
/// CollisionSystem does.
SystemDesc rebind_system();
SystemDesc mapping_system();

}  // namespace xcut
