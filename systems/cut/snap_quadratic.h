#pragma once
// The snapping cutter on quadratic elements, 10-node tetrahedra and 6-node triangles (docs/elements.md,
// "The snapping baseline on quadratic tetrahedra"). The cutter works on the corners as for linear elements (moves nodes onto the cut,
// adds edge points, subdivides, duplicates across the cut); this part keeps the quadratic field:
//   - a node moved onto the cut and an edge point take the position and velocity the field had at
//     their new rest point (the curved edge's, not the chord's);
//   - every piece is a quadratic element of its own (a triangle's piece: a 6-node triangle, its slots
//     3 and 7-9 repeating nodes 0 and 4 as QuadraticElements keeps them): a mid-edge node per edge of
//     its final DOF nodes,
//     at the edge's midpoint at rest, shared by the pieces that share the edge (so by pieces on one
//     side of the cut only), its state the field's before the cut at that point, on the piece's side.
// A quadratic field is its own interpolant on any sub-tetrahedron, so a cut changes no position
// where the tissue was quadratic (tested): the energy jumps only by what the subdivision cannot hold.
#include <array>
#include <cstdint>
#include <vector>

#include "engine/world.h"

namespace xcut {

/// The quadratic field before a snapping cut changes the mesh, kept to place what the cut makes.
struct SnapQuadraticField {
    bool active = false;  ///< the world has quadratic elements
    std::vector<Vec3> rest, position, velocity;        ///< per DOF node [m, m, m/s]
    std::vector<std::array<int, 4>> corners;           ///< per force element: its corner nodes
    std::vector<double> weight;                        ///< per force element
    std::vector<int> of_element;                       ///< per force element: its quadratic entry, -1
    std::vector<std::array<int, 10>> nodes;            ///< per quadratic entry
    std::vector<int8_t> piece_side;                    ///< per piece slot (SnapMesh::piece_side)
    std::vector<uint8_t> piece_live;                   ///< per piece slot (SnapMesh::piece_live)
    std::vector<int8_t> sign;                          ///< per mesh node: its side (EnrichedDofs::sign)
};

/// The field as it is now (inactive, and nothing copied, when the world has no quadratic element).
SnapQuadraticField keep_quadratic_field(const World& w);

/// Places the nodes the cut moved onto it (`moved`) and the edge points it made (DOF nodes from
/// `first_point` on) on the field before the cut, at their new rest points.
void place_on_quadratic_field(World& w, const SnapQuadraticField& before, const std::vector<int>& moved, int first_point);

/// Gives every live piece among `pieces` (those the cut made or whose nodes it rewrote) its quadratic
/// entry: its corners and a mid-edge node per edge, made where no piece had that edge before. Makes
/// the quadratic incidence again. Call after the pieces have their final DOF nodes and rest shapes,
/// before the masses are lumped: a mid-edge node no live element holds any more then gets no mass
/// (and is held).
void build_quadratic_pieces(World& w, const SnapQuadraticField& before, const std::vector<int>& pieces);

}  // namespace xcut
