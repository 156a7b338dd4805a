#pragma once
// Makes the quadratic tetrahedra of the materials that ask for them ("element": "quadratic"):
// mid-edge nodes shared by the elements around each edge, their incidence and their lumped masses
// (components/quadratic_elements.h, systems/kernels/quadratic_tet.h).
#include "engine/world.h"

namespace xcut {

/// Whether any material of the world is quadratic.
bool has_quadratic_material(const World& world);
/// Appends a mid-edge node per edge of the mesh elements of quadratic materials (rest and position
/// at the edge's midpoint) as mesh nodes, and fills world.quadratic. Called by build_bodies before
/// the masses are lumped; a 2D mesh with a quadratic material is refused (std::invalid_argument).
void build_quadratic_elements(World& world);
/// The node -> quadratic element incidence, over every DOF node (phantoms included), from
/// QuadraticElements::nodes: made again when elements are added (a cut's sides).
void build_quadratic_incidence(World& world);
/// HRZ mass of the mid-edge node i: 4 rho V / 27 from each quadratic element on its edge [kg].
double quadratic_edge_mass(const World& world, int i);
/// Holds each mid-edge node on the axes both its corners are held on, at the midpoint of their
/// prescribed positions: a clamped face stays clamped along its edges.
void constrain_edge_nodes(World& world);

}  // namespace xcut
