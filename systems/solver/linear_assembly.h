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
#include "systems/kernels/block_sparse.h"
#include "systems/step_term.h"

namespace xcut {

/// Rebuilds the block pattern when the elements' node ids changed since it was built (a split, a
/// remesh); returns whether it did.
bool ensure_linear_pattern(World& world);

/// Fills the values for this step's terms (systems/step_term.h: row terms, then the mass, then the
/// scattered terms) at their current linearization (the pattern must be current).
void assemble_step_matrix(World& world, const StepOperator& op, double mass_scale, double stiff_scale);

/// y = A x for the assembled A (3 entries per DOF node).
void linear_multiply(const LinearSystem& A, const Eigen::VectorXd& x, Eigen::VectorXd& y);
/// AV = A V, every column of V in one pass over A (six at a time): each column's sums are
/// linear_multiply's, in its order. Six separate products took 1.3-1.7 ms at 53k tets, this 0.85-1.1.
void linear_multiply_columns(const LinearSystem& A, const Eigen::MatrixXd& V, Eigen::MatrixXd& AV);
/// The block rows [lo, hi) of y = A x (y sized by the caller), on the calling thread.
void linear_multiply_rows(const LinearSystem& A, int lo, int hi, const Eigen::VectorXd& x, Eigen::VectorXd& y);

/// The inverses of A's 3x3 diagonal blocks, 9 per node (row-major): the block Jacobi preconditioner.
void block_diagonal_inverse(const LinearSystem& A, std::vector<double>& inverse);

}  // namespace xcut
