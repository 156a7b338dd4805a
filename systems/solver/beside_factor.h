#pragma once
// The cholesky and direct methods' preconditioner when a term is kept beside the assembly (the
// crack tips' condensed amplitudes, systems/cut/crack_tip_system.h): CHOLMOD's supernodal factor of
// the sparse system the CG operator is the Schur complement of,
//
//   M = [ A      s C^T           ]      S(M) = A - s C^T H^-1 C = A + s K_t,
//       [ s C    s (H + eps D_H) ]
//
// (BesideBlock, systems/step_term.h). Solving M [z; y] = [r; 0] gives z = (A + s K_t)^-1 r: the
// exact inverse of CG's operator at the factor's linearization, where A's own factor leaves the
// term's low-rank part to CG (problem 6's plate at 10 cells: 126 iterations). The amplitudes'
// stiffness is semi-definite (the branch functions' exact dependencies, docs/xfem.md), so eps = 1e-8
// of its diagonal is added: C has no part along those directions, and elsewhere the preconditioner
// moves by 1e-8 relative. Its fill stays local (the amplitudes couple nodes of the tip's zone only),
// so it costs about what A's factor does. Held axes: C's columns dropped (A holds them as 1).
//
// Used while the block stands still: renewed when it changes, and kept as A's own factor is (aged
// by solves and CG iterations). A block that changed at this step and at one of the two before (a
// blade that carries its tip rebuilds the zone at each stride it moves, and its old M preconditions no
// better than A's own factor) gets no factor of M: a factor every step cost that scene more than
// the CG iterations it saved. The cholesky method then solves it with the factor in use and the
// block beside it (systems/solver/beside_augment.h: sparse solves for the amplitudes' columns,
// no factorization; a factor made in the step with factor_delay 0 is viewed for it); the direct
// method, with A's factor and the term left to CG (its columns anew every step). A static solve's
// block is built once.
// In dynamic steps, cholesky with its factor renewed off the step (solver.factor_delay > 0, the
// default) makes no M at all: the factor in use with the block beside it serves a standing block
// too. M factored in the step stalled the step that needed it: a front's first step (the block
// is new) 10-20 ms and the step where the blade stopped 8-9 ms, against a 5-6 ms median, on the
// default skin with a front; a standing tip's steps cost about 0.5 ms more beside the factor than
// with M (docs/xfem.md, Crack fronts in 3D). Static solves (M once) and factor_delay 0 keep M.
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <cstdint>

#include "components/linear_system.h"
#include "systems/solver/beside_augment.h"
#include "systems/step_term.h"

namespace xcut {

struct BesideFactor {
    Eigen::SparseMatrix<double> matrix;  ///< M's lower triangle (all the factor's Lower view reads)
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt;
    uint64_t topology = 0;      ///< A's pattern it was made for
    uint64_t version = 0;       ///< the term's beside_version it was made for
    uint64_t jumps = 0;         ///< the jumping terms' jump_version it was made for (grasps)
    // Whether the block moves (a blade that carries its tip rebuilds the zone at each stride it moves):
    uint64_t seen_version = 0;  ///< the version at the last solve
    int changed_step = -1000;   ///< the step it last changed at
    int changed_before = -1000; ///< the step it changed at before that
    int base = 0;               ///< 3 per DOF node: A's rows
    double ratio = 0.0;         ///< stiff_scale / mass_scale it was made for (mass 0: stiff_scale)
    bool ok = false;
    int age = 0;                ///< solves since it was computed
    int last_iterations = 0;    ///< CG iterations of the last solve with it
    double lnz = 0.0;           ///< non-zeros of its L
    /// While the block moves: no factor of M, but the factor in use with the block beside it
    /// (systems/solver/beside_augment.h), made again as the block moves.
    BesideAugment moving;

    /// z = the first `base` entries of M^-1 [r; 0] (takes the CHOLMOD lock).
    void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;
};

/// Relative regularization of the block's H in M (its diagonal's share).
constexpr double kBesideRegularization = 1e-8;

/// Builds M from the assembled A (as filled for this step), the block and stiff_scale s, with the
/// held axes of `mask` (0) dropped from C, and factors it on the calling thread. Returns f.ok (false
/// if CHOLMOD found M not positive definite).
bool factor_beside(const LinearSystem& A, const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask,
                   BesideFactor& f);

}  // namespace xcut
