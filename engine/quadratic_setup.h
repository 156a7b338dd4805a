#pragma once
// Makes the quadratic tetrahedra of the materials that ask for them ("element": "quadratic"):
// mid-edge nodes shared by the elements around each edge, their incidence and their lumped masses
// (components/quadratic_elements.h, systems/kernels/quadratic_tet.h).
#include "engine/world.h"

namespace xcut {

/// Whether any material of the world is quadratic.
bool has_quadratic_material(const World& world);
/// Appends a mid-edge node per edge of the mesh elements of quadratic materials (rest and position
/// at the edge's midpoint) as mesh nodes, and fills world.quadratic (10-node tetrahedra; on a 2D
/// mesh, 6-node triangles). Called by build_bodies before the masses are lumped.
void build_quadratic_elements(World& world);
/// A triangle's slots for the absent fourth corner and its edges (QuadraticElements::planar): node 0
/// and node 4 again (their shape functions are zero); nothing for a tetrahedron.
inline void fill_absent_slots(const QuadraticElements& q, std::array<int, 10>& ids) {
    if (!q.planar) return;
    ids[3] = ids[0];
    ids[7] = ids[8] = ids[9] = ids[4];
}
/// The node -> quadratic element incidence, over every DOF node (phantoms included), from
/// QuadraticElements::nodes: made again when elements are added (a cut's sides).
void build_quadratic_incidence(World& world);
/// Node i's HRZ mass from the quadratic entries that do not go through the linear share
/// (element_mass_share): 4 rho V w / 27 from each whole element it is a mid-edge node of, and its
/// side's mass from each side of a cut element it is a vertex of (QuadraticElements::side_masses) [kg].
double quadratic_node_mass(const World& world, int i);
/// Force element e's quadratic entry (a mesh element's, or one side's of a cut quadratic element),
/// -1 for a linear element.
int quadratic_entry(const World& world, int e);
/// The mid-edge node of force element e's edge between its local corners i and j, -1 if e is
/// linear.
int mid_edge_node(const World& world, int e, int i, int j);
/// Whether force element e is one side of a cut quadratic element (its masses are its side's).
bool is_quadratic_side(const World& world, int e);
/// Holds each mid-edge node on the axes both its corners are held on, at the midpoint of their
/// prescribed positions: a clamped face stays clamped along its edges.
void constrain_edge_nodes(World& world);

}  // namespace xcut
