#pragma once
// SnapCutSystem: the classic snapping-and-subdivision cutter (Serby et al. 2001 for snapping;
// Bielser et al. 2003 for subdivision; the hybrid of Steinemann et al. 2006; SOFA's incision, which
// the paper's Fig. 9-10 compare with). It consumes the same CutEvents as the EnrichmentSystem — the
// CutSystem decides which elements are split, for both cutters — and changes the mesh instead of
// enriching it:
//  - a crossing within `threshold` x the edge's length of a node moves that node onto the cut
//    (rest and current position, velocity interpolated along the edge), unless the node is held, or
//    on the boundary and the edge is not, or the move would invert an element;
//  - otherwise the crossing becomes a new node on the edge (state interpolated), and every element
//    holding that edge is bisected on it (systems/kernels/snap_split_patterns.h): split elements into
//    pieces on either side of the cut, whole neighbours conformingly;
//  - a node of the cut surface (an edge point or a snapped node) is duplicated once the elements
//    around it fall apart into groups that touch only across the cut: one copy per group, so the
//    sides separate where the cut has gone through and stay joined at the crack front;
//  - masses are re-lumped from the new elements, the change rescaled so the total is conserved; the
//    visual and collision surfaces are rebuilt as the boundary of the changed mesh, so the wound
//    shows and the surfaces stay closed.
// Limits: one cut per element (as for XFEM); a node snaps once; incisions closer than about one
// element can meet an element already split by the other and leave it uncut there.
#include <vector>

#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// Sizes the cutter's per-node and per-element arrays and finds the boundary (O(mesh), once).
void prepare_snap_cut(World& world);
/// Applies `world.pending_cuts` (and clears it); returns the number of mesh elements split.
int apply_snap_events(World& world);
/// The elements carrying material now (weight > 0): untouched mesh elements and live pieces.
std::vector<int> live_elements(const World& world);
/// The mesh node or edge point a DOF node copies (itself if it is one).
int snap_root(const World& world, int node);
/// Whether a root lies on a cut surface (an edge point or a snapped node).
bool snap_surface_root(const World& world, int root);

/// Appends a DOF node with the state of `from`, or interpolated from `from` to b at t if b >= 0
/// (rest, position, velocity, CG's first guess; held on the axes both are held on); no mass yet.
int add_snap_node(World& world, int from, int b = -1, double t = 0.0);

/// The system; prepares the world's cutter state at once (scene load), so a cut does not pay it.
SystemDesc snap_cut_system(World& world);

}  // namespace xcut
