#pragma once
// Assembly of the implicit Euler step's matrix into world.linear (components/linear_system.h):
//   A = mass_scale M + stiff_scale (K + K_c),  mass_scale = 1 + h alpha,  stiff_scale = h^2 + h beta,
// K the rotated corotational stiffness (paper App. B; blocks from systems/kernels/corotational_kernel.h)
// of every element, mesh and virtual (XFEM: the enriched DOFs are the phantom nodes of the virtual
// elements, paper eq. 4-6), K_c the contact penalty stiffness (systems/collision_system.h), held axes
// filtered (row and column dropped, diagonal 1).
//
// Each block row is summed by one thread in the incidence's element order, the same order the
// matrix-free gather uses: the values are bit-identical for any thread count, with no atomics.
// The matrix-free product (systems/force_system.h) stays the reference this one is tested against.
#include <Eigen/Core>

#include "engine/world.h"
#include "systems/kernels/solver/block_sparse.h"
#include "systems/step_term.h"

namespace xcut {

/// Rebuilds the block pattern when the elements' node ids changed since it was built (a split, a
/// remesh); returns whether it did. After a split (the mesh's elements unchanged, virtual elements
/// and nodes changed or added) only the rows of the changed elements' nodes and of the new nodes
/// are gathered and searched; the others keep their columns, their blocks shifted: the same pattern
/// as one gathered whole (LinearPattern.*): 0.4-0.8 ms a split on the 1 mm skin and the 20k-tet
/// block, against 3.0 and 1.4-2.6 ms gathered whole. A remesh, quadratic elements or a first build
/// gather every row.
/// The values are left unset: assemble_step_matrix sets them.
bool ensure_linear_pattern(World& world);

/// Fills the values for this step's terms (systems/step_term.h: row terms, then the mass, then the
/// scattered terms) at their current linearization (the pattern must be current).
void assemble_step_matrix(World& world, const StepOperator& op, double mass_scale, double stiff_scale);

/// Copies A's pattern (when it differs from into's) and values into `into`, for a preconditioner
/// built off the step from a matrix the step changes next: in into's storage, grown with room
/// (engine/vector_room.h), so a copy kept from build to build lands in pages already touched.
void copy_linear_system(const LinearSystem& A, LinearSystem& into);

}  // namespace xcut
