#pragma once
// The Cholesky factor the cholesky and direct methods keep (components/linear_system.h holds it
// opaque): CHOLMOD's supernodal factor (Chen, Davis, Hager & Rajamanickam, ACM TOMS 35(3), 2008)
// of the scalar copy of the step's A. When it is renewed off the step
// (systems/solver/factor_background.h), the step solves with it through views of its supernodes
// (systems/solver/lower_factor.h: Eigen's dense kernels, no BLAS), so that the background thread
// can compute the next one with BLAS meanwhile (Debian's serial OpenBLAS is not safe to call from
// two threads at once). With a grown system (a cut added DOFs since it was computed) it keeps
// solving through an augmented block (systems/solver/factor_augment.h).
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <omp.h>

#include "systems/solver/factor_augment.h"
#include "systems/step_term.h"

namespace xcut {

/// Eigen's CHOLMOD wrapper with its factor in reach (to convert it, and for L and its permutation).
class OpenCholmod : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> {
public:
    cholmod_factor* factor() const { return m_cholmodFactor; }
};

/// The lock around every CHOLMOD call that may call BLAS (a supernodal factorization or solve) or
/// open OpenMP regions, process-wide: Debian's serial OpenBLAS is not safe to call from two threads
/// at once (two simulations stepped from two Python threads corrupted each other's factors without
/// it). Inside it CHOLMOD's own OpenMP regions run on the calling thread: Debian's CHOLMOD 3 opens
/// 4-thread regions in its supernodal factorization, whose wake-ups beside the engine's threads
/// cost more than they save on two cores (the default scene ran 20-40 % slower); the setting is
/// the calling thread's own (libgomp 12 keeps max-active-levels per thread).
std::mutex& cholmod_blas_lock();
template <class F>
void with_cholmod_blas(F&& f) {
    std::lock_guard<std::mutex> lock(cholmod_blas_lock());
    const int levels = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
    try {
        f();
    } catch (...) {
        omp_set_max_active_levels(levels);
        throw;
    }
    omp_set_max_active_levels(levels);
}

/// What a factor computed off the step is made from, in storage handed on from factor to factor:
/// the step's A, copied in the step that asks (so that asking allocates nothing in the step), and
/// its scalar copy, made off the step and factored there. Fresh pages cost a virtual machine of
/// this project's kind 4-10 ms in the step; off it, the scalar copy of the skin at 1 mm elements
/// (12 MB) took 1-27 ms of the background thread's CPU time in fresh pages against 1 ms in kept
/// ones, time taken from the step's threads on two cores.
struct FactorSnapshot {
    LinearSystem block;
    Eigen::SparseMatrix<double> scalar;
};

struct LinearFactor {
    explicit LinearFactor(bool viewed = false) : is_viewed(viewed) {}
    LinearFactor(const LinearFactor&) = delete;
    LinearFactor& operator=(const LinearFactor&) = delete;

    /// The scalar copy of A it was computed from (a factor made in the step keeps it for the next
    /// one's values; one made off the step leaves it in its FactorSnapshot, and this is empty).
    Eigen::SparseMatrix<double> matrix;
    bool is_viewed = false;              ///< solved through `lower` (renewed off the step), not by CHOLMOD
    OpenCholmod llt;
    uint64_t topology = 0;     ///< pattern the symbolic analysis was made for
    bool ok = false;           ///< the last numeric factorization succeeded
    int last_iterations = 0;   ///< CG iterations of the last solve with this factor
    int computed_step = 0;     ///< World::step of the matrix it was computed from
    double lnz = 0.0;          ///< non-zeros of L
    /// Set by compute_factor from a process-wide count, so no two factorizations share one (a
    /// factor is computed again in place, and a new one may take a freed one's address): what a
    /// block built on the factor is keyed by (systems/solver/beside_augment.h).
    uint64_t serial = 0;

    /// make_single from this many non-zeros of L on (single_precision_from), when is_viewed.
    double single_from = std::numeric_limits<double>::infinity();
    /// Views of L's supernodes (systems/solver/lower_factor.h) when is_viewed: the step's solves
    /// and the augmented block use them.
    std::unique_ptr<LowerFactor> lower;
    FactorAugment augment;     ///< the grown system's block, when A has DOFs the factor has not
    /// The jumping terms' block A held when it was factored (StepOperator::jump_blocks): a step
    /// whose block differs solves through the difference (systems/solver/beside_augment.h).
    BesideBlock jumps;
    /// The terms' jump_version and A's pattern `jumps` was last found equal to the step's block
    /// at (jumps_keyed): a step with the same key has the same block, unbuilt.
    uint64_t jumps_key = 0;
    bool jumps_keyed = false;
    /// What a successor computed off the step is copied from, in storage handed on from factor to
    /// factor (FactorSnapshot).
    std::shared_ptr<FactorSnapshot> snapshot;

    /// z = A^-1 r with the factor: through `lower` (no BLAS), else CHOLMOD's solve (the caller
    /// holds with_cholmod_blas).
    void solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;
};

/// The non-zeros of L from which a viewed factor's solves run in single precision, for
/// solver.factor_precision ("auto", "double", "single").
double single_precision_from(const std::string& precision);

/// Analyses `f.matrix` (when `analyse`) and factors it on the calling thread, under
/// with_cholmod_blas, and makes f.lower when f.is_viewed. Returns f.ok.
bool compute_factor(LinearFactor& f, bool analyse);


}  // namespace xcut
