#include "systems/solver/cholesky_factor.h"

#include <atomic>
#include <limits>

#include "systems/solver/cholmod_pages.h"

namespace xcut {

namespace {
/// CHOLMOD allocates through the kept pages from the start of the process (before any factor
/// exists: a block must be freed by the functions that allocated it).
[[maybe_unused]] const bool kPagesKept = (keep_cholmod_pages(), true);
/// The step's solves through a factor's views are split into two bins of subtrees (the two
/// threads xcut is tuned for; more threads leave the rest idle in them, one runs the serial solve)
/// when L has at least this many non-zeros; the CG then runs as a team at any size. Measured
/// (alternated runs, 2 threads, split against not): the default skin (315k non-zeros, 3.9k DOFs)
/// 1.08x the steps/s (8 pairs, 0.98-1.26x), hand_dorsum (7.4k DOFs) 1.26-1.44x (3 pairs), the skin at 1 mm
/// (4.1M) 1.36x the solver's time; the 2k-tet block (164k) 0.93x (one run each of the solver suite).
constexpr int kSolveBins = 2;
constexpr double kSplitNonzeros = 250e3;
/// solver.factor_precision "auto": a viewed factor's solves run in single precision
/// (make_single, systems/solver/lower_factor.h) when L has at least this many non-zeros (8 MB in
/// double, beyond what the caches keep between solves on the machines measured). Measured (2
/// threads, alternated runs, the same CG counts both ways): the skin at 1 mm with cholesky (4.1 M
/// non-zeros) 1.35-1.45x the solver's median time; hand_dorsum (1.0 M) 1.0-1.3x; the default skin
/// (315 k) within noise, so it keeps double (and its bits).
constexpr double kSingleNonzeros = 1e6;
}  // namespace

double single_precision_from(const std::string& precision) {
    if (precision == "single") return 0.0;
    if (precision == "double") return std::numeric_limits<double>::infinity();
    return kSingleNonzeros;
}

std::mutex& cholmod_blas_lock() {
    static std::mutex lock;
    return lock;
}

void LinearFactor::solve(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
    if (lower) return lower->solve(r, z);
    z = llt.solve(r);
}

bool compute_factor(LinearFactor& f, bool analyse) {
    static std::atomic<uint64_t> factorizations{0};
    f.serial = ++factorizations;
    f.lower.reset();
    f.augment.ok = false, f.augment.topology = 0;
    with_cholmod_blas([&] {
        if (analyse) f.llt.analyzePattern(f.matrix);
        f.llt.factorize(f.matrix);
    });
    f.ok = f.llt.info() == Eigen::Success;
    f.lnz = f.llt.cholmod().lnz;
    const cholmod_factor* L = f.llt.factor();
    if (!f.ok || !f.is_viewed) return f.ok;
    if (!L->is_super || !L->is_ll || L->xtype != CHOLMOD_REAL || L->itype != CHOLMOD_INT) return f.ok = false;
    f.lower = std::make_unique<LowerFactor>();
    view_supernodes(static_cast<int>(L->n), static_cast<int>(L->nsuper), static_cast<const int*>(L->super),
                    static_cast<const int*>(L->pi), static_cast<const int*>(L->px), static_cast<const int*>(L->s),
                    static_cast<const double*>(L->x), static_cast<const int*>(L->Perm), *f.lower);
    split_solves(*f.lower, kSolveBins, kSplitNonzeros);
    if (f.lnz >= f.single_from) make_single(*f.lower);
    return f.ok;
}

}  // namespace xcut
