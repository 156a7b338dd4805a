#pragma once
// The kept Cholesky factor with a moving term's block beside it: the cholesky method's
// preconditioner while a blade carries its crack tip (the zone is built again at each stride it moves,
// systems/cut/crack_tip_system.h), where a factor of the whole system each step costs more than it
// saves (systems/solver/beside_factor.h) and A's factor alone leaves the tips' term to CG.
//
// The term is the Schur complement of [A, s C^T; s C, s H'] (BesideBlock; H' = H + eps diag H as in
// beside_factor.h). The factor in use solves A's part, through its augmented block when A has grown
// by phantoms since (systems/solver/factor_augment.h, jump basis T); the amplitudes are one more
// block on it, eliminated as the phantoms are (Yeung, Crouch & Pothen 2016's augmented matrices):
//   E = T^T (s C^T), its base rows E_b and its phantom rows E_p;
//   Y_E = L^-1 P E_b = X_S E_S, with S the factor's rows E_b touches (the DOFs of the zone's
//   elements), X_S = L^-1 P I_S and E_S the block's values on them;
//   Z = E_p - Y_g^T Y_E,  D = s H' - Y_E^T Y_E,  with Y_g, S_g = L_g L_g^T the phantoms' block;
//   V = L_g^-1 Z,  S_E = D - V^T V = L_E L_E^T (dense, one row per amplitude).
// Applied to [r; 0]: v = L^-1 P g1; p = L_g^-1 (g2 - Y_g^T v); y = L_E^-T L_E^-1 (-Y_E^T v - V^T p);
// a = L_g^-T (p - V y); u = P^T L^-T (v - Y_g a - Y_E y); z = T (u, a). The exact inverse of the
// whole system's Schur complement A_kept - s C^T H'^-1 C, for one solve with the kept factor and
// products with sparse X_S, Y_g and small dense blocks.
//
// What is kept: X_S (sparse forward solves, 8 columns side by side), G = X_S^T X_S and F = Y_g^T X_S stay
// while the factor and S stay: a tip moving inside one cell changes E_S's values, not S, so most moving
// steps pay only the small dense products (E^T G E, F E, V, S_E's Cholesky). When S changes over the same
// factor, the columns of the rows it keeps stay with their entries of G and their columns of F (the same
// bits as made again), and only the new rows are solved; when a split adds phantoms, only F's rows of the
// new ones are made (extend_augment keeps the columns of Y_g it held). On the default skin with a blade's
// front, F made in full at every such change took 0.24 ms of a 0.7 ms build at the median (timers put in
// for one run, 2026-12-06).
// Solving the amplitudes' columns every step instead took 0.3-0.44 ms a step on the face skin and
// saved nothing (docs/xfem.md, Solvers).
//
// The same block carries a jump of an assembled term (StepTerm::jump_block: grasps' jaws that
// closed or opened since the factor was made): the term's block now, with its H, and its block as
// the factor was made, with H negated, so that A_kept - s C^T H'^-1 C = A_kept + s (K_now - K_then),
// the step's A up to the elements' own drift since (Woodbury's identity by the augmented matrix).
// A stiffness that adds has H < 0, so S_E is then indefinite and factored by LDL^T (Eigen's
// pivoted LDLT); a tip's block alone keeps its LLT.
#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "components/linear_system.h"
#include "systems/solver/factor_augment.h"
#include "systems/solver/lower_factor.h"
#include "systems/step_term.h"

namespace xcut {

struct BesideAugment {
    uint64_t factor = 0;           ///< LinearFactor::serial it was built on (X_S with it)
    uint64_t version = 0;          ///< the term's beside_version it was built for
    uint64_t topology = 0;         ///< A's pattern it was built for
    int phantom_columns = 0;       ///< the factor's augmented columns it was built over
    double stiff_scale = 0.0;      ///< s it was built for
    // Kept while the factor and the set S of the factor's rows E_b touches stay (a tip moving inside
    // one cell): X_S = L^-1 P I_S by sparse columns (rows in the factor's order), G = X_S^T X_S,
    // F = Y_g^T X_S (for `f_columns` phantom columns).
    std::vector<int> s_rows;
    std::vector<int> x_start{0}, x_row;
    std::vector<double> x_value;
    Eigen::MatrixXd G, F;
    int f_columns = -1;            ///< F's rows made (-1: none)
    std::vector<int> f_fresh;      ///< F's columns still to make for those rows (rows new in S)
    // Per block: E_b restricted to S (|S| x amplitudes), so Y_E = X_S E_S.
    Eigen::MatrixXd E;
    Eigen::MatrixXd V;             ///< L_g^-1 Z (phantom columns x amplitudes)
    Eigen::LLT<Eigen::MatrixXd> schur;  ///< of S_E = D - V^T V
    Eigen::LDLT<Eigen::MatrixXd> schur_indefinite;  ///< of S_E when H has a negative diagonal entry
    bool indefinite = false;
    bool with_term = false;        ///< it holds a moving term's block (else jumps only)
    BesideBlock jumps;             ///< the jumping terms' block now it was built for
    bool ok = false;
    bool unbuilt = false;          ///< holds columns made off the step for a new factor, not yet the block
    int solves = 0;                ///< CG solves it preconditioned
    int s_builds = 0;              ///< times S changed (X_S was built)
    int s_solved = 0;              ///< columns of X_S solved for in the step (the others kept)
    int s_seeded = 0;              ///< columns of X_S made off the step and taken (take_beside_columns)

    int amplitudes() const { return static_cast<int>(E.cols()); }
};

/// Appends `more`'s rows to `into`, its H times `h_sign`.
void append_block(BesideBlock& into, const BesideBlock& more, double h_sign);
/// Whether two blocks hold the same rows and entries in the same order.
bool same_block(const BesideBlock& a, const BesideBlock& b);

/// Builds b for `block` at stiff_scale s beside the factor `lf` (LinearFactor::serial `factor`; its
/// augmented block g when A has grown, else null), the held axes of `mask` (0) dropped from C.
/// False (b.ok false) if S_E is not positive definite (or, with a negative H, singular): the caller
/// keeps the factor with the term beside it.
bool build_beside_augment(const LinearSystem& A, const LowerFactor& lf, uint64_t factor, const FactorAugment* g,
                          const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask, BesideAugment& b);

/// The columns of X_S and their G for `rows` (sorted) over the factor `lf` (LinearFactor::serial
/// `factor`), into an empty b: what build_beside_augment would solve for them (the same bits), made
/// off the step for a successor factor (systems/solver/factor_background.h).
void solve_beside_columns(const LowerFactor& lf, uint64_t factor, const std::vector<int>& rows, BesideAugment& b);
/// Gives b the columns `made` holds (solve_beside_columns), b's block to be built at its next use;
/// that build keeps the columns of the rows its S shares with them.
void take_beside_columns(BesideAugment&& made, BesideAugment& b);

/// z = T M^-1 T^T r through the kept factor `lf`, its phantoms' block g (null: none) and the
/// amplitudes' block b (null: none; else the first A-sized part of M^-1 [r; 0], see above); r and z
/// of A's size. With neither block, the factor's own solve. Outside any parallel region.
void apply_augmented(const LowerFactor& lf, const FactorAugment* g, const BesideAugment* b, const Eigen::VectorXd& r,
                     Eigen::VectorXd& z);
/// What a team's threads share in apply_augmented_in_team.
struct AugmentScratch {
    LowerFactor::Scratch lower;  ///< the factor's split solve (LowerFactor::prepare sizes it)
    Eigen::VectorXd g1, p;       ///< T^T r; the phantoms' part of the solution
};
/// The same, by every thread of a team, the factor's solves split among them
/// (LowerFactor::solve_in_team: the same bits on any number of threads); sh.lower prepared, z sized.
void apply_augmented_in_team(const LowerFactor& lf, const FactorAugment* g, const BesideAugment* b,
                             const Eigen::VectorXd& r, Eigen::VectorXd& z, AugmentScratch& sh);

}  // namespace xcut
