#pragma once
// The copies of a mesh node (its DOF nodes: the real node and phantoms) by material connectivity,
// the virtual node algorithm's rule (Molino, Bao & Fedkiw 2004; Sifakis et al. 2007), kept in the
// phantom-node storage of the paper's Fig. 4 (docs/xfem.md, Node copies).
//
// Around mesh node j, each element holds one fragment of material (a whole element) or two (a cut
// element's sides). Two fragments hold the same copy of j when their elements share a face through j
// and their parts of that face overlap (a side is on a face where one of the face's nodes is on that
// side; the two sides of a cut never overlap). On a progressive front a tip element's sides are one
// material at the nodes of a split edge the blade has not crossed yet (the cut's extension ahead of
// the blade). Each class of that union is one copy: the class holding j's own material (a whole
// element, or a side j is on) is the real node, every other class a phantom. One cut through an
// element gives the paper's crack-front rule (§3.5); incisions that meet need no rule of their own.
#include <vector>

#include "engine/world.h"

namespace xcut {

/// Gives each fragment around each mesh node j of `nodes` (in their order) its copy of j: writes
/// the vertices at j of the virtual elements of the cut elements around j (which must exist), adds
/// a phantom for a class that has none (starting from the state of the copy its material used:
/// continuous), and sets EnrichedDofs::front_fixed[j]. Appends to `changed` the cut elements whose
/// vertices changed, and every cut element around j when j gained a copy (duplicates possible).
/// A class keeps the smallest phantom its fragments used that no earlier class kept.
void assign_node_copies(World& world, const std::vector<int>& nodes, std::vector<int>& changed);

}  // namespace xcut
