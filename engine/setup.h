#pragma once
// Turns a validated mesh into the world's node and element components: rest shape gradients, rest
// volumes, lumped masses, identity rotations, constraint flags and the node -> element incidence.
#include <string>
#include <vector>

#include "engine/mesh_data.h"
#include "engine/world.h"

namespace xcut {

/// Fills world.nodes and world.elements from `mesh` (all elements use material 0 unless
/// `material_of_cell` is given). Lumped mass: each element's rho V split equally over its nodes
/// (exact total mass; the standard lumping for linear simplices).
void build_bodies(World& world, const MeshData& mesh, const std::vector<uint16_t>& material_of_cell = {});

/// Appends a copy of element e (nodes, rest shape, rotation, material, region, body) with the given
/// weight, as a cutter makes a virtual element or a piece of it; returns the new element's index.
int append_element_copy(Elements& elements, int e, double weight);

/// Rest volume V (2D: area x thickness) and Dm^-1 of element e from its nodes' rest positions.
void compute_rest_shape(World& world, int e);

/// Lumped masses from the elements: rho V weight / (nodes per element) to each node. For a cut
/// element this is the phantom-node lumping: each side's share goes to that side's vertices, which
/// equals the block-diagonal lumping of Menouillard et al. (IJNME 74, 2008) in the enriched DOFs.
void lump_masses(World& world);
/// The same for the listed nodes only, through both incidences (after a cut: O(cut), not O(mesh)).
void relump_nodes(World& world, const std::vector<int>& nodes);

/// Sets nodes.fixed from world.constraints (boxes and node lists); in 2D every node's z is held.
void apply_constraints(World& world);

/// Adds a scalpel with no contact shape: its cutting edge from `tip` (deep end) to `heel` in the
/// tool frame [m], moved along `trajectory` and starting at its first keyframe. Returns its index.
int add_scalpel(World& world, const std::string& name, const std::vector<Keyframe>& trajectory, const Vec3& tip,
                const Vec3& heel);

}  // namespace xcut
