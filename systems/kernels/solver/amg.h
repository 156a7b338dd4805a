#pragma once
// Smoothed-aggregation algebraic multigrid for the step's elasticity system, used as the CG
// preconditioner of the "amg" linear method (systems/solver/linear_solver.h).
//
// Method: Vaněk, Mandel & Brezina, "Algebraic multigrid by smoothed aggregation for second and
// fourth order elliptic problems", Computing 56 (1996), with the rigid-body near-null space of
// elasticity (translations and infinitesimal rotations about the nodes' current positions), as in
// ML/MueLu and PyAMG's smoothed_aggregation_solver:
//  - strength: nodes i, j are strongly coupled when |A_ij|_F^2 >= theta^2 |A_ii|_F |A_jj|_F, with
//    theta = 0.04 on the finest level, halved on each coarser one (Vaněk et al. 1996, eq. 3.2, take
//    0.08; the choice is measured in amg_setup.cpp);
//  - aggregation: the standard three passes (a node with all its strong neighbours free roots an
//    aggregate; leftovers join a neighbouring aggregate; what is still left roots its own);
//  - tentative prolongator: per aggregate, the near-null rows orthonormalised (Gram-Schmidt, a mode
//    dropped when its remainder falls below 1e-8 of its length: held axes, a 2D mesh's z);
//  - smoothed prolongator P = (I - 4/3 / lambda_max D^-1 A) P_tent, D = diag(A); Galerkin A_c = P^T A P;
//  - smoother: Chebyshev polynomial of D^-1 A on [lambda_max / 15, 1.1 lambda_max], degree 2, the same
//    before and after, so the V-cycle is symmetric (Adams, Brezina, Hu & Tuminaro, "Parallel
//    multigrid smoothing: polynomial versus Gauss-Seidel", J. Comput. Phys. 188, 2003);
//    lambda_max from 20 Lanczos steps (Jacobi-preconditioned CG from a fixed vector: deterministic),
//    capped by Gershgorin's bound; the Chebyshev polynomial stays below 1 up to upper + lower =
//    1.1 (1 + 1/15) lambda_max, so it tolerates an estimate up to 14 % low;
//  - coarsest level (at most kCoarsest DOFs, or when coarsening stalls): sparse LDL^T.
//
// The hierarchy is built from one step's A and kept, like the Cholesky factor: rotations change
// slowly, and the finest level's residual and smoothing always use the current A. The setup runs on
// one thread; the V-cycle runs on the calling OpenMP team (worksharing loops over rows, each row by
// one thread: the same bits for any team size) down to the first level with fewer than 50,000
// non-zeros, and from there on one thread of the team.
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <vector>

#include "components/linear_system.h"

namespace xcut {

using CsrMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

/// A coarse level's operator for the cycle: a sparse matrix in single precision, each row stored as
/// runs of consecutive columns (a column and a length; the values packed). The cycle's vectors and
/// sums stay double: the cycle is a fixed linear operator either way, CG's own product and residual
/// are double, and a V-cycle is bound by memory traffic, which single precision halves
/// (mixed-precision multigrid preconditioning, as in hypre's and MueLu's; Tsai, Beams & Anzt,
/// "Three-precision algebraic multigrid on GPUs", Future Gener. Comput. Syst. 149, 2023). Runs,
/// because an aggregate's modes and a node's three DOFs are numbered together: on the 53k-tet block
/// a run holds 8 (P), 11 (R) and 16 (the first coarse A) entries on average, so a row needs one
/// column index a run instead of one an entry, and its sums run four entries at a time.
struct RunMatrix {
    int row_count = 0, column_count = 0;
    std::vector<int> row_start{0};  ///< row i's runs: [row_start[i], row_start[i + 1])
    std::vector<int> run_column;    ///< each run's first column
    std::vector<int> run_start{0};  ///< run k's values: [run_start[k], run_start[k + 1])
    std::vector<float> value;       ///< the runs' values, in order

    int rows() const { return row_count; }
    int cols() const { return column_count; }
    long nonZeros() const { return static_cast<long>(value.size()); }
};

/// M stored by runs (M's explicit entries, zeros included).
RunMatrix to_runs(const CsrMatrix& M);

/// C = A B (systems/kernels/solver/amg_setup.cpp): the same pattern and bits as Eigen's
/// conservative sparse product, built in C's own storage.
CsrMatrix sparse_product(const CsrMatrix& A, const CsrMatrix& B);

/// y = M v on the calling thread, with the cycle's row kernel (single-precision values, double sums).
void run_product(const RunMatrix& M, const Eigen::VectorXd& v, Eigen::VectorXd& y);

/// One level: its matrix (coarse levels; the finest uses the step's block matrix), the operators to
/// the next coarser level and the smoother's data, plus scratch vectors for the cycle.
struct AmgLevel {
    RunMatrix A;                       ///< this level's matrix (empty on the finest)
    RunMatrix P, R;                    ///< prolongation from the next coarser level, R = P^T
    Eigen::VectorXd inverse_diagonal;  ///< 1 / diag(A) [this level's units]
    double lambda_max = 1.0;           ///< estimate of the largest eigenvalue of D^-1 A [-]
    Eigen::VectorXd x, b, r, d, t;     ///< the cycle's vectors on this level
};

struct AmgHierarchy {
    std::vector<AmgLevel> levels;                      ///< [0] the finest
    std::vector<float> finest;                         ///< the current A's blocks in single precision, column-major
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> coarsest;
    uint64_t topology = 0;   ///< the pattern it was built for
    int age = 0;             ///< solves since it was built
    int first_iterations = 0, last_iterations = 0;  ///< CG iterations of its first and last solves
    /// stiff_scale / mass_scale of the A it was built for [s^2]: lambda_max(D^-1 A) does not grow
    /// as that ratio falls (a substep), so the kept smoother bounds hold below it, not above.
    double stiffness_ratio = 0.0;
    bool ok = false;         ///< built, and the coarsest factor succeeded
    /// Built off the step: the copy of the step's A it was built from, whose storage the next
    /// renewal's copy reuses (systems/solver/amg_background.h); the hierarchy does not read it.
    std::shared_ptr<LinearSystem> snapshot;
};

/// Coarsening stops at this many DOFs (then LDL^T).
constexpr int kAmgCoarsest = 1500;
/// A kept hierarchy is renewed when a solve needs more than growth x its first solve's CG
/// iterations + slack (it has aged: rotations, dt or contacts moved A away from the setup's).
constexpr int kAmgRenewGrowth = 2, kAmgRenewSlack = 4;

/// Non-zeros the hierarchy holds (every level's A, P and R, the coarsest factor): its memory at
/// 12 bytes each (value and index).
double amg_nonzeros(const AmgHierarchy& h);

/// Builds the hierarchy for the block matrix A (its current values), near-null space from
/// `position` (one per block row [m]), rows with mask 0 held. Runs on the calling thread.
void build_amg(const LinearSystem& A, const std::vector<Eigen::Vector3d>& position, const Eigen::VectorXd& mask,
               AmgHierarchy& h);

/// Carries the hierarchy over to a pattern that only added DOF nodes after the existing ones (a cut:
/// XFEM's phantom nodes, a snap cut's new nodes): the new rows get no coarse representation (zero
/// rows of P), so only the finest level's smoothing acts on them, and the setup is not paid at the
/// cut step. The kept policy renews it when CG slows. False (nothing changed) when the hierarchy has
/// a single level or the pattern has fewer rows.
bool amg_extend(AmgHierarchy& h, const LinearSystem& A);

/// Refreshes the finest level from the current A (each solve: dt or contacts may have changed it
/// since the setup): its single-precision blocks and its diagonal; lambda_max is kept.
void amg_update_finest(AmgHierarchy& h, const LinearSystem& A);

/// z = V-cycle(r) on the current block matrix A: called by every thread of an OpenMP team (its loops
/// are orphaned worksharing loops); z is whole when it returns. Unmasked: the caller masks.
void amg_cycle_in_team(AmgHierarchy& h, const LinearSystem& A, const Eigen::VectorXd& r, Eigen::VectorXd& z);

}  // namespace xcut
