#pragma once
// The amg method beside a term whose stiffness couples a small zone densely: the crack tips'
// condensed amplitudes (StepTerm::beside_block: K_t = -C^T H^-1 C on the zone's DOFs, applied beside
// A in CG's product). The multigrid cycle M is built from A alone, so CG on A + s K_t needed 3-6x
// the iterations of the same plate without the tip (problem 6 with its tip enriched, 80-320 cells:
// 151-304 against 47-49, docs/BENCHMARKS.md, accuracy). The cycle is wrapped here in a symmetric
// multiplicative Schwarz step with an exact solve on the zone, the two-subspace case of the
// symmetric multiplicative Schwarz methods (Smith, Bjørstad & Gropp, *Domain Decomposition*,
// Cambridge University Press, 1996; Toselli & Widlund, *Domain Decomposition Methods: Algorithms
// and Theory*, Springer, 2005):
//
//   B = Z + (I - Z Â) M (I - Â Z),   Z = P S^-1 P^T,   S = P^T Â P,   Â = A + s K_t,
//
// P the zone's DOFs (the coupling's columns that are free). B is symmetric, and positive definite
// when M is: CG's preconditioner stays SPD. S is dense (K_t couples the whole zone) and small: the
// tip's zone holds some 100-300 DOFs in 2D. An application is M's cycle plus work on the zone and
// the rows beside it: z1 = Z r; r1 = r - Â z1 (zero on the zone, A's columns of the zone off it);
// z = z1 + M r1; z += Z (r - Â z). No product over the whole system.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "components/linear_system.h"
#include "systems/step_term.h"

namespace xcut {

/// Zones larger than this keep the term to CG, as before (a 3D front's zone, rebuilt with every
/// solve, would cost its dense factor at each step: 400 DOFs factor in about 2 ms).
inline constexpr int kZoneMaxDofs = 400;

struct ZoneCorrection {
    bool ok = false;
    std::vector<int> dofs;              ///< the zone's scalar DOFs (free), increasing
    Eigen::MatrixXd term;               ///< s K_t on the zone (m x m)
    Eigen::LLT<Eigen::MatrixXd> local;  ///< S = P^T (A + s K_t) P
    Eigen::VectorXd z1, g, zz;          ///< the first zone solve, the last's right-hand side, z on the zone
};

/// Builds `out` for A + stiff_scale K_t, K_t = -C^T H^-1 C from `block`, on A's free DOFs (mask 1).
/// False (out.ok false) if the zone is empty or larger than kZoneMaxDofs, or H or S is not
/// positive definite: the caller then applies M alone.
bool build_zone_correction(const LinearSystem& A, const BesideBlock& block, double stiff_scale, const Eigen::VectorXd& mask,
                           ZoneCorrection& out);

/// z = B r with the multigrid cycle `cycle(r1, z)`; called by every thread of a CG team (the zone's
/// work on one thread, the copy of r and the cycle by all); r1 is the team's scratch (sized 3 x A's
/// rows).
template <class Cycle>
void zone_corrected_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& r1,
                          Eigen::VectorXd& z, Cycle&& cycle);

/// The zone's parts of one application (zone_corrected_cycle): before the cycle, z1 = Z r and the
/// zone's columns of A z1 taken from r1 (r1 = r beforehand); after it, z += P z1 and the last zone
/// solve. On one thread.
void zone_before_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& r1);
void zone_after_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& z);

template <class Cycle>
void zone_corrected_cycle(const LinearSystem& A, ZoneCorrection& zc, const Eigen::VectorXd& r, Eigen::VectorXd& r1,
                          Eigen::VectorXd& z, Cycle&& cycle) {
    const int n = static_cast<int>(r.size());
#pragma omp for schedule(static)
    for (int i = 0; i < n; ++i) r1[i] = r[i];
#pragma omp single
    zone_before_cycle(A, zc, r, r1);
    cycle(r1, z);
#pragma omp barrier
#pragma omp single
    zone_after_cycle(A, zc, r, z);
}

}  // namespace xcut
