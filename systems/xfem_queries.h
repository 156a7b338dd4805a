#pragma once
// The XFEM queries other systems read the cut through (a seam, like systems/step_term.h): the
// surface code asks where the crack crosses an edge and whether the blade has crossed it; output
// and studies ask a node's enriched displacement. They read the cut components only (CutElements,
// EnrichedDofs); the EnrichmentSystem (systems/cut/enrichment_system.h) is what writes them.
#include "engine/world.h"

namespace xcut {

/// Mesh edge a-b has been crossed by the blade: some cut element holding it has its bit in
/// CutElements::crossed. False for an edge no cut element holds.
bool edge_crossed(const World& world, int a, int b);

/// Where the crack crosses mesh edge a -> b: the parameter from a of the point a cut element holding
/// the edge put on it, or -1 if no cut element crosses it. One crack has one point per edge: an
/// element split later takes this one, and the surface cuts along it.
double crack_edge_param(const World& world, int a, int b);

/// a_j of mesh node j (eq. 6), zero if the node has no phantom.
Vec3 enriched_displacement(const World& world, int node);
Vec3 enriched_velocity(const World& world, int node);

}  // namespace xcut
