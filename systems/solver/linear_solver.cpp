#include "systems/solver/linear_solver.h"

#include <Eigen/SparseCore>
#include <exception>

#include "engine/parallel.h"
#include "systems/kernels/solver/amg.h"
#include "systems/kernels/solver/projected_guess.h"
#include "systems/kernels/solver/team_cg.h"
#include "systems/solver/amg_background.h"
#include "systems/solver/zone_correction.h"
#include "systems/solver/beside_augment.h"
#include "systems/solver/beside_factor.h"
#include "systems/solver/cholesky_factor.h"
#include "systems/solver/factor_background.h"
#include "systems/solver/linear_assembly.h"

namespace xcut {

namespace {

/// The cholesky method renews its factor off the step (systems/solver/factor_background.h).
bool off_step_factors(const World& w) { return w.linear.method == "cholesky" && w.solver.factor_delay > 0; }

/// Factors A in the step (symbolically too when the pattern changed), solved through views of its
/// supernodes when `viewed` (a factor renewed off the step is, and one that solves with a moving
/// block beside it: beside_augment.h). False if CHOLMOD found A not SPD.
bool factorize(World& w, bool viewed) {
    LinearSystem& A = w.linear;
    if (!A.factor || A.factor->is_viewed != viewed) A.factor = std::make_shared<LinearFactor>(viewed);
    LinearFactor& f = *A.factor;
    f.single_from = single_precision_from(w.solver.factor_precision);
    const bool fresh_pattern = f.topology != A.topology || f.matrix.rows() != 3 * A.rows();
    copy_to_scalar(A, f.matrix, fresh_pattern);
    compute_factor(f, fresh_pattern);
    if (fresh_pattern) {
        f.topology = A.topology;
        ++A.symbolic_factorizations;
    }
    A.factor_nonzeros = f.lnz;
    f.computed_step = w.step;
    ++A.factorizations;
    A.factor_age = 0;
    A.step_preconditioner = 3;
    return f.ok;
}

/// Builds the amg method's hierarchy from the assembled A, for stiff_scale / mass_scale = `ratio`.
bool build_hierarchy(World& w, const Eigen::VectorXd& mask, double ratio) {
    LinearSystem& A = w.linear;
    if (!A.amg) A.amg = std::make_shared<AmgHierarchy>();
    AmgHierarchy& h = *A.amg;
    build_amg(A, w.nodes.position, mask, h);
    h.stiffness_ratio = ratio;
    ++A.factorizations;
    A.step_preconditioner = 3;
    A.factor_nonzeros = amg_nonzeros(h);
    return h.ok;
}

}  // namespace


namespace {

/// amg, off the step: a successor is asked for once a solve needs more than this growth x the
/// kept hierarchy's first count + slack (the in-step renewal waits for kAmgRenewGrowth, 2x + 4).
constexpr double kAmgEarlyGrowth = 1.5;
constexpr int kAmgEarlySlack = 2;
/// cholesky, off the step: a successor is asked for once a solve needs more than this fraction of
/// solver.refactor_iterations.
constexpr double kFactorEarlyFraction = 0.5;
/// ... or once its augmented block holds more new DOFs than this (its dense Schur complement is
/// applied every CG iteration).
constexpr int kFactorAugmentLimit = 120;
/// ... and renewed in the step past this multiple of solver.refactor_iterations.
constexpr int kFactorInStepGrowth = 4;

/// Records a CG result in `out`; whether it reached the tolerance.
bool accepted(const CgResult& cg, const CgLimits& limits, LinearSolve& out) {
    out.cg = cg;
    out.converged = cg.relative_residual <= limits.tolerance;
    return out.converged;
}

/// The preconditioner a team_cg call does not use: the row-wise one, or the whole-vector one.
void no_rows(int, int, const Eigen::VectorXd&, Eigen::VectorXd&) {}
void no_whole(const Eigen::VectorXd&, Eigen::VectorXd&) {}

/// The jacobi method: matrix-free, A p = mass_scale M p + stiff_scale K p (stiffness_product_in_team),
/// preconditioned by diag(A)^-1 (the paper's solver).
CgResult jacobi_cg(World& w, const StepOperator& op, double mass_scale, double stiff_scale, const Eigen::VectorXd& b,
                   const Eigen::VectorXd& mask, const CgLimits& limits, Eigen::VectorXd& x) {
    const int nodes = w.nodes.count();
    Eigen::VectorXd inverse(3 * nodes);
    // An axis with no stiffness and no mass in A (a static solve's 2D z axis, held) gets 1: its
    // residual is masked to 0, and 0 x infinity would be NaN.
    for (int i = 0; i < 3 * nodes; ++i) {
        const double d = mass_scale * w.nodes.mass[i / 3] + stiff_scale * w.forces.stiffness_diagonal[i];
        inverse[i] = d > 0.0 ? 1.0 / d : 1.0;
    }
    op.prepare_product(w);
    const auto product = [&](const Eigen::VectorXd& p, Eigen::VectorXd& q) {
        op.stiffness_product_in_team(w, p, q);
#pragma omp for schedule(static)
        for (int i = 0; i < 3 * nodes; ++i) q[i] = mass_scale * w.nodes.mass[i / 3] * p[i] + stiff_scale * q[i];
    };
    const auto jacobi_rows = [&](int lo, int hi, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
        for (int i = 3 * lo; i < 3 * hi; ++i) z[i] = r[i] * inverse[i];
    };
    return team_cg(nodes, product, Preconditioning::kRows, jacobi_rows, no_whole, b, mask, limits.tolerance,
                   limits.max_iterations, x);
}

/// One solve with an assembled method: A filled for this step, CG as one team per solve
/// (systems/kernels/solver/team_cg.h) with the product by rows.
class AssembledSolve {
public:
    AssembledSolve(World& w, const StepOperator& op, double stiff_scale, const Eigen::VectorXd& b,
                   const Eigen::VectorXd& mask, const CgLimits& limits, Eigen::VectorXd& x, LinearSolve& out)
        : w_(w), A_(w.linear), op_(op), stiff_scale_(stiff_scale), b_(b), mask_(mask), limits_(limits), x_(x), x0_(x),
          out_(out) {}

    bool accept(const CgResult& cg) { return accepted(cg, limits_, out_); }

    /// CG with the preconditioner given as team_cg takes it.
    template <class Rows, class Whole>
    CgResult cg(Preconditioning mode, Rows&& rows, Whole&& whole, bool heavy_preconditioner = false) {
        const LinearSystem& A = A_;
        const bool beside = op_.any_beside(w_);
        const auto product = [&](const Eigen::VectorXd& v, Eigen::VectorXd& q) {
#pragma omp for schedule(static)
            for (int i = 0; i < A.rows(); ++i) linear_multiply_rows(A, i, i + 1, v, q);
            if (beside) {  // after the rows' barrier; one thread, the others wait at the single's
#pragma omp single
                op_.add_beside_product(w_, v, q, stiff_scale_, mask_);
            }
        };
        return team_cg(A.rows(), product, mode, rows, whole, b_, mask_, limits_.tolerance, limits_.max_iterations, x_,
                       heavy_preconditioner);
    }

    CgResult block_jacobi() {
        std::vector<double> inverse;
        block_diagonal_inverse(A_, inverse);
        const auto rows = [&](int lo, int hi, const Eigen::VectorXd& r, Eigen::VectorXd& z) {
            for (int i = lo; i < hi; ++i)
                z.segment<3>(3 * i) =
                    Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(inverse.data() + 9 * i) * r.segment<3>(3 * i);
        };
        return cg(Preconditioning::kRows, rows, no_whole);
    }

    /// A kept preconditioner (a factor, a hierarchy), renewed as the policy says; a solve above
    /// tolerance with an old one renews it and retries; one that cannot be made (not SPD) falls
    /// back to block Jacobi for this solve. solved(iterations) keeps its bookkeeping.
    template <class Renew, class Ok, class Solve, class Solved>
    void with_kept(bool stale, Renew&& renew, Ok&& ok, Solve&& solve, Solved&& solved) {
        const bool fresh = stale && renew();
        if (ok() && accept(solve())) return solved(out_.cg.iterations);
        if (!fresh && renew()) {
            x_ = x0_;
            out_.refactored = true;
            const int spent = out_.cg.iterations;
            accept(solve());
            solved(out_.cg.iterations - spent);
            out_.cg.iterations += spent;
            if (out_.converged) return;
        }
        if (!ok()) {
            x_ = x0_;
            const int spent = out_.cg.iterations;
            accept(block_jacobi());
            out_.cg.iterations += spent;
        }
    }

    /// The amg method; `ratio` = stiff_scale / mass_scale of this step's A.
    void amg(double ratio) {
        const SolverSettings& s = w_.solver;
        const bool failed_off_step = take_due_hierarchy();
        AmgHierarchy* h = A_.amg.get();
        if (h && h->ok && h->topology != A_.topology && amg_extend(*h, A_)) ++A_.extensions;
        const bool ratio_grew = h && ratio > (1.0 + 1e-9) * h->stiffness_ratio;
        bool stale = !h || !h->ok || h->topology != A_.topology || h->age >= s.refactor_every ||
                     h->last_iterations > kAmgRenewGrowth * h->first_iterations + kAmgRenewSlack || ratio_grew ||
                     failed_off_step;
        // Aged only (it still preconditions, within its smoother's bounds): renewed off the step
        // (systems/solver/amg_background.h) while this one goes on. Off the step the renewal is
        // cheap, so it is asked for earlier, at half the growth (kAmgEarlyGrowth): the successor
        // arrives about when the kept one would have been renewed in the step.
        const bool aging = h && h->ok && h->last_iterations > kAmgEarlyGrowth * h->first_iterations + kAmgEarlySlack;
        // Started after this step's solve (below), from the same A, as cholesky's successor is.
        bool successor = false;
        std::shared_ptr<LinearSystem> snapshot;
        if ((stale || aging) && h && h->ok && h->topology == A_.topology && !ratio_grew && !failed_off_step &&
            s.renew_delay > 0) {
            if (!A_.pending_amg) successor = true, snapshot = h->snapshot;
            stale = false;
        }
        if (A_.pending_amg || successor) A_.step_preconditioner = std::max(A_.step_preconditioner, 1);
        const auto renew = [&] {
            const bool ok = build_hierarchy(w_, mask_, ratio);
            h = A_.amg.get();
            return ok;
        };
        // A term beside A with a small dense zone (the crack tips): the cycle with an exact solve on
        // the zone around it (systems/solver/zone_correction.h); made again for every solve.
        ZoneCorrection zone;
        BesideBlock block;
        const StepTerm* term = op_.block_term(w_);
        const bool zoned = term && term->beside_block(w_, block) && build_zone_correction(A_, block, stiff_scale_, mask_, zone);
        Eigen::VectorXd scratch(zoned ? 3 * A_.rows() : 0);
        const auto cycle = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
            const auto plain = [&](const Eigen::VectorXd& q, Eigen::VectorXd& out) { amg_cycle_in_team(*h, A_, q, out); };
            if (zoned) return zone_corrected_cycle(A_, zone, r, scratch, z, plain);
            plain(r, z);
        };
        const auto solve = [&] {
            amg_update_finest(*h, A_);
            return cg(Preconditioning::kTeam, no_rows, cycle);
        };
        const auto solved = [&](int iterations) {
            if (h->age++ == 0) h->first_iterations = iterations;
            h->last_iterations = iterations;
        };
        with_kept(stale, renew, [&] { return h && h->ok; }, solve, solved);
        if (successor) {
            A_.pending_amg = start_background_hierarchy(A_, snapshot, w_.nodes.position, mask_, ratio, w_.step,
                                                        w_.step + s.renew_delay);
            ++A_.background_builds;
        }
    }

    /// Takes the hierarchy built off the step that is due at this step (waiting for it if it is
    /// not ready); true if its setup failed (the step then builds one itself, as a failed setup
    /// always did).
    bool take_due_hierarchy() {
        if (!A_.pending_amg || A_.pending_amg->due_step > w_.step) return false;
        double wait = 0.0;
        std::shared_ptr<AmgHierarchy> h = take_when_due(*A_.pending_amg, wait);
        A_.pending_amg.reset();
        record_wait(wait);
        if (!h->ok) return true;
        // Held to the count its predecessor started at: its own first solve comes a few steps after
        // the state it was built for, and a count inflated by that would let it age unrenewed.
        if (A_.amg && A_.amg->age > 0) h->first_iterations = A_.amg->first_iterations, h->age = 1;
        A_.amg = std::move(h);
        ++A_.factorizations, ++A_.swaps;
        A_.factor_nonzeros = amg_nonzeros(*A_.amg);
        A_.step_preconditioner = std::max(A_.step_preconditioner, 2);
        return false;
    }

    /// CG preconditioned by the factor f (through its augmented block and `beside`, if given):
    /// through the views of L (no BLAS) by the whole team (LowerFactor::solve_in_team, the solves
    /// split among its threads), else by CHOLMOD's solve on one thread.
    CgResult factor_cg(const LinearFactor& f, bool augmented, const BesideAugment* beside) {
        AugmentScratch scratch;
        const auto solve_in_team = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
            if (beside || augmented)
                return apply_augmented_in_team(*f.lower, augmented ? &f.augment : nullptr, beside, r, z, scratch);
            f.lower->solve_in_team(r, z, scratch.lower, LowerFactor::NoBetween{});
        };
        const auto solve_by_cholmod = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) {
            with_cholmod_blas([&] { f.solve(r, z); });
        };
        if (!f.lower) return cg(Preconditioning::kSingle, no_rows, solve_by_cholmod);
        f.lower->prepare(scratch.lower);
        return cg(Preconditioning::kTeam, no_rows, solve_in_team, f.lower->split.bins > 0);
    }

    /// Whether the factor made in the step is solved through views of its supernodes: off the step
    /// as a background one is, and beside a moving block (prepare_beside), except direct's (its
    /// factor of every step would solve all the block's columns anew: the block is left to CG).
    bool viewed_factor() const { return off_step_factors(w_) || (moving_term_ && A_.method != "direct"); }

    /// cholesky / direct: CG preconditioned by CHOLMOD's factor (factor_cg).
    /// cholesky renews it off the step (systems/solver/factor_background.h): at a cut the old one
    /// goes on through an augmented block, an aged one as it is, until the successor is due.
    void cholesky(double mass_scale) {
        if (beside_cholesky(mass_scale)) return;
        const SolverSettings& s = w_.solver;
        const bool off_step = off_step_factors(w_);
        const bool failed_off_step = take_due_factor();
        LinearFactor* f = A_.factor.get();
        bool augmented = off_step && f && f->ok && f->topology != A_.topology && augment_for_grown_system(w_, *f, mask_);
        // A term whose stiffness jumped since the factor was made (grasps): solved beside it, and a
        // successor asked for at once.
        StepJumps now;
        now.key = op_.jump_version(w_) * 1000003u + A_.topology;
        const bool jumped = jumped_since(f, now);
        const bool aged = f && (A_.factor_age >= s.refactor_every || f->last_iterations > s.refactor_iterations);
        // Off the step the renewal costs the step nothing, so it is asked for at half the count
        // (kFactorEarlyFraction): the successor arrives about when the kept one would have aged.
        const bool aging = f && f->last_iterations > kFactorEarlyFraction * s.refactor_iterations;
        const bool augment_grew = augmented && f->augment.columns() > kFactorAugmentLimit;
        // Started after this step's solve (below), from the same A: the solve keeps the team's
        // threads (while a job runs the team has one fewer: engine/background_threads.h).
        const bool successor = off_step && f && f->ok && (augment_grew || aged || aging || jumped) && !A_.pending_factor &&
                               !failed_off_step;
        const std::shared_ptr<FactorSnapshot> snapshot = successor ? f->snapshot : nullptr;
        // Renewed in the step all the same when its successor would come too late: CG needed more
        // than kFactorInStepGrowth x refactor_iterations (a large step that turned the elements).
        const bool spent = f && f->last_iterations > kFactorInStepGrowth * s.refactor_iterations;
        const bool viewed = viewed_factor();  // a kept factor made without the views is made again
        const bool stale = !f || !f->ok || A_.method == "direct" || failed_off_step || (viewed && !f->lower) ||
                           (f->topology != A_.topology && !augmented) || ((aged || jumped) && !off_step) || spent;
        if (A_.pending_factor || successor) A_.step_preconditioner = std::max(A_.step_preconditioner, 1);
        if (augmented) ++A_.augmented_steps;
        // A term's block that moves (a blade carrying its tip) and the jumps since the factor was
        // made: one more augmented block on the factor in use, made again for each factor,
        // augmented block, zone and jump (systems/solver/beside_augment.h).
        BesideAugment* beside = nullptr;
        bool renewed = false;
        const auto prepare_beside = [&] {
            beside = nullptr;
            const bool jump = jumped && f->ok && !renewed;  // a factor renewed in the step holds them
            if ((!moving_term_ && !jump) || !f || !f->ok || !f->lower || (f->topology != A_.topology && !augmented)) return;
            if (!A_.beside_factor) A_.beside_factor = std::make_shared<BesideFactor>();
            const FactorAugment* g = augmented ? &f->augment : nullptr;
            const uint64_t version = moving_term_ ? moving_term_->beside_version(w_) : 0;
            BesideAugment& t = A_.beside_factor->moving;
            const bool same = !t.unbuilt && t.factor == f->serial && t.version == version &&
                              t.with_term == (moving_term_ != nullptr) && t.topology == A_.topology &&
                              t.phantom_columns == (g ? g->columns() : 0) && t.stiff_scale == stiff_scale_ &&
                              same_block(t.jumps, jump ? built(now) : BesideBlock{});
            if (!same) {
                BesideBlock block;
                if (moving_term_ && !moving_term_->beside_block(w_, block)) return;
                if (jump) append_block(block, built(now), 1.0), append_block(block, f->jumps, -1.0);
                t.version = version, t.topology = A_.topology, t.with_term = moving_term_ != nullptr;
                t.jumps = jump ? built(now) : BesideBlock{};
                build_beside_augment(A_, *f->lower, f->serial, g, block, stiff_scale_, mask_, t);
                t.phantom_columns = g ? g->columns() : 0, t.stiff_scale = stiff_scale_;
            }
            if (t.ok) beside = &t, ++t.solves;
        };
        const auto renew = [&] {
            const bool ok = factorize(w_, viewed);
            f = A_.factor.get();
            f->jumps = built(now), f->jumps_key = now.key, f->jumps_keyed = true;
            augmented = false, renewed = true;
            return ok;
        };
        const auto solved = [&](int iterations) {
            f->last_iterations = iterations;
            ++A_.factor_age;
        };
        with_kept(stale, renew, [&] { return f && f->ok; },
                  [&] {
                      prepare_beside();
                      return factor_cg(*f, augmented, beside);
                  },
                  solved);
        start_successors(successor, snapshot, now);
    }

    /// cholesky / direct beside a term that gives its block (the crack tips): CG preconditioned by
    /// the factor of the whole sparse system (systems/solver/beside_factor.h), computed in the step
    /// and kept as A's own is: renewed when the block, A's pattern or the scales change, when it
    /// has preconditioned refactor_every solves, when CG needed more than refactor_iterations with
    /// it, and every solve for direct. False if no term gives a block, while the block moves from
    /// step to step, and in dynamic steps of cholesky with its factor renewed off the step, whose
    /// factor in use solves with the block beside it whether it moves or stands (beside_factor.h
    /// says why).
    bool beside_cholesky(double mass_scale) {
        moving_term_ = nullptr;
        StepTerm* term = op_.block_term(w_);
        if (!term) return false;
        const SolverSettings& s = w_.solver;
        std::shared_ptr<BesideFactor>& f = A_.beside_factor;
        if (!f) f = std::make_shared<BesideFactor>();
        const uint64_t version = term->beside_version(w_);
        if (version != f->seen_version) f->changed_before = f->changed_step, f->changed_step = w_.step, f->seen_version = version;
        if (f->changed_step == w_.step && w_.step - f->changed_before <= 2) return moving_term_ = term, false;  // a moving block
        if (mass_scale > 0.0 && off_step_factors(w_)) return moving_term_ = term, false;  // no step factors M
        const double ratio = mass_scale > 0.0 ? stiff_scale_ / mass_scale : -stiff_scale_;  // static solves: -s
        const uint64_t jumps = op_.jump_version(w_);  // M holds A's grasps as they were: made again as they jump
        const bool stale = !f->ok || f->version != version || f->jumps != jumps || f->topology != A_.topology ||
                           f->base != 3 * A_.rows() || f->ratio != ratio || f->age >= s.refactor_every ||
                           f->last_iterations > s.refactor_iterations || A_.method == "direct";
        const auto renew = [&] {
            BesideBlock block;
            if (!term->beside_block(w_, block)) return false;
            const bool ok = factor_beside(A_, block, stiff_scale_, mask_, *f);
            f->ratio = ratio, f->version = version, f->jumps = jumps;
            ++A_.factorizations;
            A_.factor_age = 0;
            A_.factor_nonzeros = f->lnz;
            A_.step_preconditioner = 3;
            return ok;
        };
        const auto solved = [&](int iterations) {
            f->last_iterations = iterations;
            ++f->age;
        };
        with_kept(stale, renew, [&] { return f->ok; },
                  [&] { return cg(Preconditioning::kSingle, no_rows, [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) { f->solve(r, z); }); },
                  solved);
        return true;
    }

    /// Takes the factor computed off the step that is due at this step (waiting for it if it is
    /// not ready); true if it failed (the step then factors A itself, as a failed factorization
    /// always did). One older than the factor in use (a solve renewed it in a step since) is dropped.
    bool take_due_factor() {
        if (!A_.pending_factor || A_.pending_factor->due_step > w_.step) return false;
        double wait = 0.0;
        const std::shared_ptr<PendingFactor> pending = std::move(A_.pending_factor);
        std::shared_ptr<LinearFactor> f = take_when_due(*pending, wait);
        const int requested = pending->requested_step;
        record_wait(wait);
        if (!f->ok) return true;
        if (A_.factor && A_.factor->ok && A_.factor->computed_step > requested) {
            retire_factor(std::move(f));
            return false;
        }
        if (A_.factor) hand_on_columns(A_.factor->augment, f->augment);
        retire_factor(std::move(A_.factor));
        A_.factor = std::move(f);
        if (A_.beside_factor) take_successor_columns(*pending, *A_.factor, A_.beside_factor->moving, wait), record_wait(wait);
        A_.factor_age = w_.step - requested;
        ++A_.factorizations, ++A_.symbolic_factorizations, ++A_.swaps;
        A_.factor_nonzeros = A_.factor->lnz;
        A_.step_preconditioner = std::max(A_.step_preconditioner, 2);
        return false;
    }

private:
    /// The jumping terms' block at this step (StepOperator::jump_blocks), built on first use.
    struct StepJumps {
        uint64_t key = 0;  ///< the terms' jump_version and A's pattern
        BesideBlock block;
        bool built = false;
    };
    const BesideBlock& built(StepJumps& j) {
        if (!j.built) j.block = op_.jump_blocks(w_), j.built = true;
        return j.block;
    }
    /// Whether the jumping terms' block differs from the one factor f was made with: built and
    /// compared only when the key moved since it last matched.
    bool jumped_since(LinearFactor* f, StepJumps& j) {
        if (!f || !f->ok || (f->jumps_keyed && f->jumps_key == j.key)) return false;
        if (!same_block(built(j), f->jumps)) return true;
        f->jumps_key = j.key, f->jumps_keyed = true;
        return false;
    }

    /// After the step's solve: the successor factor, if asked for (A copied into `snapshot`, the
    /// kept factor's storage), and the columns its moving block needs once it is
    /// kSuccessorColumnsLead steps from due.
    void start_successors(bool successor, std::shared_ptr<FactorSnapshot> snapshot, StepJumps& now) {
        const SolverSettings& s = w_.solver;
        if (successor) {
            A_.pending_factor = start_background_factor(A_, std::move(snapshot), built(now), w_.step, w_.step + s.factor_delay,
                                                        single_precision_from(s.factor_precision));
            ++A_.background_builds;
        }
        const bool columns_due = A_.pending_factor && w_.step + kSuccessorColumnsLead >= A_.pending_factor->due_step;
        if (columns_due && A_.beside_factor && A_.factor)
            start_successor_columns(w_, *A_.pending_factor, A_.beside_factor->moving, *A_.factor);
    }

    /// A step's wait for a preconditioner computed off the step [ms].
    void record_wait(double wait) {
        A_.step_wait_ms += wait, A_.wait_ms_total += wait, A_.wait_ms_max = std::max(A_.wait_ms_max, wait);
    }

    World& w_;
    LinearSystem& A_;
    const StepOperator& op_;
    double stiff_scale_;
    const Eigen::VectorXd& b_;
    const Eigen::VectorXd& mask_;
    const CgLimits limits_;
    Eigen::VectorXd& x_;
    const Eigen::VectorXd x0_;
    LinearSolve& out_;
    StepTerm* moving_term_ = nullptr;  ///< a term whose block moves from step to step (cholesky)
};

}  // namespace

namespace {

/// AV = A V, column by column, with this step's A: the assembled matrix, or matrix-free for jacobi.
void step_product(World& w, const StepOperator& op, double mass_scale, double stiff_scale, const Eigen::MatrixXd& V,
                  Eigen::MatrixXd& AV) {
    if (w.linear.method != "jacobi") {
        linear_multiply_columns(w.linear, V, AV);
        if (!op.any_beside(w)) return;  // the common case: no mask, no copies in the step's guess
        const Eigen::VectorXd mask = free_mask(w);
        for (Eigen::Index j = 0; j < V.cols(); ++j) {
            Eigen::VectorXd column = AV.col(j);
            op.add_beside_product(w, V.col(j), column, stiff_scale, mask);
            AV.col(j) = column;
        }
        return;
    }
    AV.resize(V.rows(), V.cols());
    Eigen::VectorXd v, out;
    for (Eigen::Index j = 0; j < V.cols(); ++j) {
        v = V.col(j);
        op.stiffness_product(w, v, out);
        for (Eigen::Index i = 0; i < v.size(); ++i) out[i] = mass_scale * w.nodes.mass[i / 3] * v[i] + stiff_scale * out[i];
        AV.col(j) = out;
    }
}

/// A solve; with `history`, x's first guess is projected from the kept solutions when they were
/// solved for the same system, and the solution is kept (systems/kernels/solver/projected_guess.h).
LinearSolve solve(World& w, const StepOperator& op, double mass_scale, double stiff_scale, const Eigen::VectorXd& b,
                  const Eigen::VectorXd& mask, Eigen::VectorXd& x, const CgLimits& limits, SolutionHistory* history,
                  const StepMatrix* filled) {
    LinearSystem& A = w.linear;
    if (!filled) fill_step_matrix(w, op, mass_scale, stiff_scale);
    const bool matrix_free = A.method == "jacobi";  // resolved by fill_step_matrix
    const GuessKey key{static_cast<int>(b.size()), w.elements.count(), matrix_free ? 0 : A.topology};
    if (history && history->key == key &&
        projected_guess(*history, [&](const Eigen::MatrixXd& V, Eigen::MatrixXd& AV) {
            step_product(w, op, mass_scale, stiff_scale, V, AV);
        }, b, x))
        ++A.projected_guesses;
    LinearSolve out;
    if (matrix_free) {
        accepted(jacobi_cg(w, op, mass_scale, stiff_scale, b, mask, limits, x), limits, out);
    } else {
        AssembledSolve solve(w, op, stiff_scale, b, mask, limits, x, out);
        if (A.method == "block_jacobi") solve.accept(solve.block_jacobi());
        else if (A.method == "amg") solve.amg(stiff_scale / mass_scale);
        else solve.cholesky(mass_scale);
    }
    if (history && out.converged) remember_solution(*history, key, w.solver.guess_history, x, mask);
    return out;
}

}  // namespace

void prepare_linear_solver(World& w, const StepOperator& op) {
    LinearSystem& A = w.linear;
    if (A.method.empty()) A.method = resolve_linear_method(w, &A.method_why);
    if (w.nodes.count() == 0 || (A.method != "cholesky" && A.method != "amg")) return;
    const double start = wall_seconds();
    const StepScales scales = step_scales(w.solver, w.solver.dt);
    op.linearize(w);
    fill_step_matrix(w, op, scales.mass, scales.stiffness);
    if (A.method == "amg") build_hierarchy(w, free_mask(w), scales.stiffness / scales.mass);
    else factorize(w, off_step_factors(w)), A.factor->jumps = op.jump_blocks(w);
    // The first successor's copy of A (the default skin asks for one at its second step, as it
    // sags) goes into storage touched here, at load, not in fresh pages in the step that asks.
    if (off_step_factors(w) && A.factor) {
        copy_linear_system(A, (A.factor->snapshot = std::make_shared<FactorSnapshot>())->block);
        warm_pages_for_successor(*A.factor);
    }
    A.load_setup_ms = 1e3 * (wall_seconds() - start);
}

LinearSolve solve_linear(World& w, const StepOperator& op, double mass_scale, double stiff_scale,
                         const Eigen::VectorXd& b, const Eigen::VectorXd& mask, Eigen::VectorXd& x, const CgLimits& limits) {
    return solve(w, op, mass_scale, stiff_scale, b, mask, x, limits, nullptr, nullptr);
}

LinearSolve solve_step_linear(World& w, const StepOperator& op, double mass_scale, double stiff_scale,
                              const Eigen::VectorXd& b, const Eigen::VectorXd& mask, Eigen::VectorXd& x,
                              const StepMatrix* filled) {
    return solve(w, op, mass_scale, stiff_scale, b, mask, x,
                 CgLimits{w.solver.cg_tolerance, w.solver.cg_max_iterations}, &w.linear.history, filled);
}

StepMatrix fill_step_matrix(World& w, const StepOperator& op, double mass_scale, double stiff_scale) {
    LinearSystem& A = w.linear;
    if (A.method.empty()) A.method = resolve_linear_method(w, &A.method_why);
    StepMatrix out;
    if (A.method == "jacobi") return out;
    out.assembled = true;
    ensure_linear_pattern(w);
    assemble_step_matrix(w, op, mass_scale, stiff_scale);
    return out;
}

}  // namespace xcut
