#pragma once
// EnrichmentSystem: applies the cut events that cutters queued during the step (one sync point for
// every topology change, like a deferred command buffer). For each newly split element it
//  - fixes the Heaviside sign H_j of each node once (the first cut that meets the node decides;
//    a node exactly on the cut goes above: fixed tie-break), so every element sharing a node sees
//    the same H_j;
//  - computes the exact volume fractions V_a/V, V_b/V;
//  - gives each node its copies (the real node and phantom DOF nodes, components/cut_elements.h)
//    by material connectivity around it (systems/cut/node_copies.h): one cut through an element
//    gives the node one enriched DOF unless the crack-front rule (§3.5) holds it at zero (an
//    enriched DOF on a crossed edge that the cut element shares with an uncut element stays at zero
//    until that neighbour is cut too, and on a progressive front one on a split edge the blade has
//    not crossed yet: docs/xfem.md); incisions that meet at a node give it a copy per part;
//  - for an event on an element already cut (a tip element), marks the edges the blade has crossed
//    since and releases the nodes no longer held;
//  - creates the two virtual elements (above, below) with weights V_s/V and their own rotations,
//    whose vertices are those copies;
//  - re-lumps masses (each side's share to its own vertices; momentum is conserved because a new
//    phantom starts at its node's position and velocity) and rebuilds the force incidence.
#include <vector>

#include "engine/scheduler.h"
#include "engine/world.h"
#include "systems/xfem_queries.h"

namespace xcut {

/// Smallest weight V_s/V a side carries [-]. A cut exactly through a face leaves one side with zero
/// volume: its phantom vertices would have no mass and no stiffness (a singular system). The floor
/// keeps them attached with 1e-9 of the element's stiffness and mass, far below any tolerance.
inline constexpr double kMinSideFraction = 1e-9;

/// Sizes the per-node and per-element XFEM arrays (O(mesh), once: call at scene load so the first
/// cut does not pay for it).
void prepare_enrichment(World& world);

/// Entries of room past each element and node array's end kept resident for the splits to come
/// (a batch appends a few hundred at most).
inline constexpr size_t kRoomAhead = 4096;

/// Faults in the next kRoomAhead entries of room of the arrays a split appends to, on the
/// background thread (engine/room_ahead.h), when the arrays have come within half of that of the
/// room asked for before (a job every ~2,000 virtual elements, not every split: each wakes the
/// background thread, and while it runs the step's teams have one thread fewer).
/// prepare_enrichment and every batch that splits call it.
void fault_room_ahead(World& world);

/// Applies `world.pending_cuts` (and clears it): an event for an element an earlier event of the
/// same batch splits cuts it again after it is split, where the world cuts again. Returns the
/// number of elements split, and of splits again.
int apply_cut_events(World& world);

SystemDesc enrichment_system();

}  // namespace xcut
