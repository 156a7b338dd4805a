#include "systems/solver/cholesky_factor.h"

#include <atomic>

#include "systems/solver/cholmod_pages.h"

namespace xcut {

namespace {
/// CHOLMOD allocates through the kept pages from the start of the process (before any factor
/// exists: a block must be freed by the functions that allocated it).
[[maybe_unused]] const bool kPagesKept = (keep_cholmod_pages(), true);
}  // namespace

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
    return f.ok;
}

}  // namespace xcut
