#pragma once
// Quadrature over one side of a cut tetrahedron, for the quadratic element's enriched sides
// (docs/elements.md, "Cutting quadratic elements: the design", step 1).
//
// A side's strain is linear in the element, so its stiffness integrand is quadratic and the side is
// not its volume fraction times the element (as it is for the linear element). The cut divides the
// rest tetrahedron into a corner tetrahedron and a prism, or two prisms; a prism is three
// tetrahedra, and Keast's 4-point rule of degree 2 on each (Keast, "Moderate-degree tetrahedral
// quadrature formulas", CMAME 55, 1986) integrates every quadratic exactly over the side: at most
// 12 points. The split is the one tet_side_volume uses (systems/kernels/cut_geometry.h): the two
// sides of a two-and-two cut share the quad face's diagonal (p_AD, p_BC), so they tile the element
// even when the four crossing points are not coplanar.
//
// Points are barycentric coordinates of the parent element and weights fractions of its rest
// volume, so a rule is made once at the split and serves any shape the element takes.
#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "systems/kernels/quadratic_tet.h"

namespace xcut {

using Tet10SideGradients = Tet10PointGradients<TetSideRule::kMaxPoints>;

/// The tetrahedra that make side `side` of a cut element, each by its 4 vertices in the parent's
/// barycentric coordinates; returns how many (0 for no node on the side, 1 for the whole element or
/// a corner alone, 3 for a prism). H: node signs; t: the crossing parameter of every crossed edge
/// (kTetEdges order, from the edge's first node), as for tet_side_volume.
int tet_side_pieces(const std::array<int8_t, 4>& H, const std::array<double, 6>& t, int side,
                    std::array<std::array<Eigen::Vector4d, 4>, 3>& pieces);

/// Keast's 4-point rule on every tetrahedron of the side.
TetSideRule tet_side_rule(const std::array<int8_t, 4>& H, const std::array<double, 6>& t, int side);

/// The shape gradients of the 10 nodes at the rule's points, for the element's Dm^-1 (`planar`: a
/// 6-node triangle's, from tri3_gradients).
Tet10SideGradients tet10_side_gradients(const Mat3& dm_inv, const TetSideRule& rule, bool planar = false);

/// The 6-node triangle's whole rule: Strang & Fix's 3 points of degree 2, L = (2/3, 1/6, 1/6) and
/// its permutations (L_3 = 0), weights 1/3: the stiffness integrand is quadratic. Made once.
const TetSideRule& tri6_rule();

/// HRZ lumped masses of one side (Hinton, Rock & Zienkiewicz, Earthq. Eng. Struct. Dyn. 4, 1976, as
/// for the whole element in quadratic_tet.h): the diagonal of the side's consistent mass,
/// int_side N_i^2, scaled to the side's volume; as fractions of rho V (the parent's rest volume), so
/// they sum to the side's volume fraction. N_i^2 is of degree 4, beyond Keast's 4 points: each
/// tetrahedron of the side takes the conical product of 4-point Gauss-Legendre rules (Stroud,
/// Approximate Calculation of Multiple Integrals, 1971, §2.7; positive weights, exact to degree 5
/// with the collapsed map's Jacobian), once at the split. The whole element gets 1/36 and 4/27.
std::array<double, 10> tet10_side_masses(const std::array<int8_t, 4>& H, const std::array<double, 6>& t, int side);

/// The 6-node triangle's side of a cut (2D), as tet_side_pieces: its triangles by their 3 vertices in
/// the parent's barycentric coordinates (L_3 = 0); returns how many (0; 1 for the whole triangle or a
/// corner alone; 2 for the quad of two corners, cut along its diagonal from the first). H: corner
/// signs; t: the crossing parameter of every crossed edge (kTriEdges order, from the edge's first
/// corner).
int tri_side_pieces(const std::array<int8_t, 3>& H, const std::array<double, 3>& t, int side,
                    std::array<std::array<Eigen::Vector4d, 3>, 2>& pieces);

/// Strang & Fix's 3 points on every triangle of the side (tri6_rule mapped; weights fractions of the
/// parent's area).
TetSideRule tri_side_rule(const std::array<int8_t, 3>& H, const std::array<double, 3>& t, int side);

/// HRZ lumped masses of one side of a 6-node triangle, as tet10_side_masses: int_side N_i^2 by the
/// collapsed product of 4-point Gauss-Legendre rules on each triangle (exact to degree 5 with the
/// Jacobian), scaled to the side's area fraction; 0 in the slots a triangle does not use. The whole
/// triangle gets 1/19 and 16/57.
std::array<double, 10> tri6_side_masses(const std::array<int8_t, 3>& H, const std::array<double, 3>& t, int side);

}  // namespace xcut
