#pragma once
// The step's linear system, assembled: A = (1 + h alpha) M + (h^2 + h beta) (K + K_c), the rotated
// corotational stiffness of every element (mesh and virtual) and the contact stiffness, stored as
// 3x3 blocks in block compressed rows (BSR). The pattern is built once and again only when the
// topology changes (an XFEM split adds DOFs and virtual elements, a snap cut remeshes); the values
// are refilled each step (systems/solver/solver_system.h). Held axes are filtered: their rows and columns
// are dropped and the diagonal set to 1, so A stays SPD.
//
// Why blocks: a node couples its 3 axes to the same neighbours, so one column index serves 9
// values; a product A p reads 76 bytes per block against 108 in scalar CSR.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace xcut {

/// A factor the solver keeps between steps (CHOLMOD's supernodal Cholesky); opaque here.
struct LinearFactor;
/// The smoothed-aggregation hierarchy the amg method keeps (systems/kernels/solver/amg.h); opaque here.
struct AmgHierarchy;
/// A hierarchy being built off the step (systems/solver/amg_background.h); opaque here.
struct PendingHierarchy;
/// A Cholesky factor being computed off the step (systems/solver/factor_background.h); opaque here.
struct PendingFactor;
/// The factor of the system a term kept beside the assembly completes (systems/solver/beside_factor.h); opaque here.
struct BesideFactor;

/// What the kept solutions of earlier steps belong to (systems/kernels/solver/projected_guess.h): a step
/// with another key starts them again (a cut changes the DOFs, the elements or the pattern). A
/// change of dt (real-time mode, a substep) keeps them: the projection is formed with the current A,
/// whatever scales it has.
struct GuessKey {
    int dofs = 0, elements = 0;
    uint64_t topology = 0;  ///< the assembled pattern (0 when matrix-free)
    bool operator==(const GuessKey&) const = default;
};

/// The velocity changes [m/s] solved in the last steps with one key, newest last, held entries zero.
struct SolutionHistory {
    GuessKey key;
    std::vector<Eigen::VectorXd> solutions;
};

/// What the block pattern was last built from, and storage kept between builds
/// (systems/solver/linear_assembly.cpp): a split changes the rows of its elements' nodes only, and
/// the others are carried over, their blocks shifted, instead of gathered and searched again.
struct PatternBuild {
    std::vector<std::array<int, 4>> elements;  ///< every element's node ids at the build
    std::vector<int> virtual_offset;           ///< the virtual incidence's offsets at the build
    int mesh_nodes = 0, mesh_elements = 0;
    /// The previous pattern while a new one is made from it (swapped with LinearSystem's).
    std::vector<int> row_offset, column, diagonal;
    std::vector<std::array<int, 4>> virtual_slot;
    std::vector<char> changed;                 ///< per block row: gathered again
    /// Each gathered row's candidate columns in one flat buffer, and where its stretch starts.
    std::vector<int> scratch, bound;
    int carried = 0;                           ///< builds that carried rows over (a test's count)
};

struct LinearSystem {
    // Pattern: block rows are DOF nodes; columns the nodes they share an element with.
    std::vector<int> row_offset;        ///< block row i's blocks: [row_offset[i], row_offset[i+1])
    std::vector<int> column;            ///< block column of each block
    std::vector<int> diagonal;          ///< per block row: the index of its diagonal block
    /// Per incidence entry (mesh incidence, then the virtual one): for each local node b of the
    /// entry's element, the block (row: the entry's node, column: node b) its term goes to.
    std::vector<std::array<int, 4>> mesh_slot, virtual_slot;
    /// The same per entry of the quadratic elements' incidence, for their 10 nodes.
    std::vector<std::array<int, 10>> quadratic_slot;
    uint64_t topology = 0;              ///< hash of the element node ids the pattern was built for
    PatternBuild pattern;               ///< what it was built from (a split rebuilds only its rows)

    // Values: 9 per block, row-major, [N/m s^2 ... ]: A's units are those of M (kg) when applied to dv.
    std::vector<double> value;

    int rows() const { return static_cast<int>(diagonal.size()); }
    int blocks() const { return static_cast<int>(column.size()); }

    // The solver's state between steps.
    std::shared_ptr<LinearFactor> factor;  ///< the preconditioner factor, if the method keeps one
    std::shared_ptr<AmgHierarchy> amg;     ///< the multigrid hierarchy, if the method is amg
    std::shared_ptr<BesideFactor> beside_factor;  ///< cholesky, direct: the factor with a beside term's block
    int factor_age = 0;                    ///< steps since the factor was computed
    int factorizations = 0;                ///< numeric factorizations (or amg hierarchies built) so far
    int symbolic_factorizations = 0;       ///< symbolic (pattern) analyses so far
    int extensions = 0;                    ///< amg hierarchies carried over to a grown pattern (amg_extend)
    double factor_nonzeros = 0.0;          ///< non-zeros of the Cholesky factor L or the amg hierarchy (12 bytes each)
    std::string method;                    ///< the method in use: jacobi, block_jacobi, amg, cholesky, direct
    std::string method_why;                ///< why (resolve_linear_method), for the SolverSystem's schedule line
    double load_setup_ms = 0.0;            ///< building the kept preconditioner at load [ms]
    SolutionHistory history;               ///< earlier steps' solutions: the next step's first guess
    int projected_guesses = 0;             ///< steps whose first guess came from them

    // Renewing the kept preconditioner off the step (amg: systems/solver/amg_background.h, cholesky:
    // systems/solver/factor_background.h).
    std::shared_ptr<PendingHierarchy> pending_amg;  ///< a hierarchy being built, if any
    std::shared_ptr<PendingFactor> pending_factor;  ///< a factor being computed, if any
    int augmented_steps = 0;  ///< cholesky: solves of a grown system through the old factor and an augmented block
    /// This step's kept preconditioner, for the metrics: 0 kept as it is, 1 aged while a renewed
    /// one is built off the step, 2 a renewed one taken into use, 3 built in the step.
    int step_preconditioner = 0;
    double step_wait_ms = 0.0;             ///< this step waited for the one built off the step [ms]
    int background_builds = 0;             ///< preconditioners asked for off the step so far
    int swaps = 0;                         ///< of those, taken into use
    double wait_ms_total = 0.0, wait_ms_max = 0.0;  ///< the steps' waits for them [ms]
};

}  // namespace xcut
