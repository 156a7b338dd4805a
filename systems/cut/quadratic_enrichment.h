#pragma once
// The quadratic element's part of a split (docs/elements.md, "Cutting quadratic elements", step 2).
// The field is the shifted Heaviside over the 10 shape functions, stored as for the linear element:
// a phantom DOF node per enriched node, the mid-edge nodes included. Each side of a cut quadratic
// element is a quadratic entry over its 10 virtual vertices (real nodes and phantoms), corotated by
// its corner element's R (the virtual force element: R_a, R_b as for the linear element) and
// integrated by its side's rule (systems/kernels/tet10_side_rule.h), with its side's HRZ masses.
#include <vector>

#include "engine/world.h"

namespace xcut {

/// Whether mesh node i is a quadratic element's mid-edge node.
bool is_edge_node(const World& w, int i);

/// Gives a side to every mid-edge node of mesh element e (quadratic; nothing for a linear one)
/// that has none yet, after its corners got theirs: a node on an edge whose corners share a side
/// takes it; on a split edge, the side of the corner its midpoint lies beside (the crossing
/// parameter t from the crack's shared edge point: t < 1/2 puts it on the far corner's side; exactly
/// 1/2 on the lower-numbered corner's).
void sign_edge_nodes(World& w, int e);

/// Appends the quadratic entries of cut element c's two virtual elements (nothing for a linear
/// element): the parent's 10 nodes, each side's rule and HRZ masses from its corners' sides and its
/// edge points. A side below kMinSideFraction of the element is floored there, as the linear
/// element's weight is.
void add_quadratic_sides(World& w, int c);

/// Appends the mid-edge nodes of the quadratic mesh elements around corner node i: those whose
/// progressive-front clause reads i's edges (a crossing of one of them releases them).
void append_edge_nodes_around(const World& w, int i, std::vector<int>& out);

/// Copies the corners of cut elements `cuts`' virtual elements (written by the node copies in
/// Elements) into their quadratic entries, and makes the quadratic incidence again.
void sync_quadratic_sides(World& w, const std::vector<int>& cuts);

/// The 10 vertices of cut element c's quadratic entries and its parent's, appended to `out`.
void append_quadratic_vertices(const World& w, int c, std::vector<int>& out);

}  // namespace xcut
