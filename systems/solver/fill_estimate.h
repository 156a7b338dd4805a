#pragma once
// The Cholesky factor's size before any factor is made: a symbolic analysis (CHOLMOD's AMD
// ordering and column counts, simplicial) of the mesh's node graph, 1/9 of the scalar pattern's
// entries, scaled to the scalar factor of 3 DOFs a node. The `auto` linear method reads it where the
// DOF count alone would pick the multigrid (systems/solver/linear_solver.cpp): a thin layer's fill
// grows like a surface mesh's, far below a block's of as many DOFs.
#include "engine/world.h"

namespace xcut {

/// Estimated non-zeros of L for the assembled 3-DOFs-a-node system of w's elements (their nodes all
/// coupled), from the node graph's AMD ordering: 9 per off-diagonal node entry of L, 6 per node
/// (its 3 x 3 diagonal block's lower triangle). 0 if CHOLMOD fails (out of memory).
double estimated_factor_nonzeros(const World& w);

}  // namespace xcut
