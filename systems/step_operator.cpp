#include "systems/step_term.h"

namespace xcut {
namespace {

/// Calls f(term, first) for each active term that `keep` keeps, in order; `first` for the first.
template <class Keep, class F>
void in_order(const std::vector<std::shared_ptr<StepTerm>>& terms, const World& world, Keep&& keep, F&& f) {
    bool first = true;
    for (const auto& t : terms)
        if (keep(*t) && t->active(world)) {
            f(*t, first);
            first = false;
        }
}

bool every(const StepTerm&) { return true; }
bool not_held(const StepTerm& t) { return !t.held(); }
bool held(const StepTerm& t) { return t.held(); }

}  // namespace

void StepOperator::linearize(World& world) const {
    for (const auto& t : terms) t->linearize(world);
}

void StepOperator::relinearize(World& world) const {
    linearize(world);
    forces(world);
}

void StepOperator::forces(World& world) const {
    in_order(terms, world, not_held, [&](StepTerm& t, bool first) { t.force(world, first); });
}

void StepOperator::stiffness_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const {
    in_order(terms, world, every, [&](StepTerm& t, bool first) { t.product(world, p, out, first); });
}

void StepOperator::stiffness_product_in_team(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const {
    in_order(terms, world, every, [&](StepTerm& t, bool first) { t.product_in_team(world, p, out, first); });
}

void StepOperator::prepare_product(World& world) const {
    for (const auto& t : terms) t->prepare_product(world);
}

void StepOperator::add_held_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const {
    in_order(terms, world, held, [&](StepTerm& t, bool) { t.product(world, p, out, false); });
}

bool StepOperator::any_held(const World& world) const {
    bool any = false;
    in_order(terms, world, held, [&](StepTerm&, bool) { any = true; });
    return any;
}

void StepOperator::add_start_forces(World& world) const {
    for (const auto& t : terms)
        if (!t->from_system() && t->active(world)) {
            t->linearize(world);
            t->force(world, false);
        }
}

void StepOperator::finish_step(World& world) const {
    for (const auto& t : terms)
        if (t->active(world)) t->finish_step(world);
}

double StepOperator::energy_now(World& world) const {
    double sum = 0.0;
    in_order(terms, world, not_held, [&](StepTerm& t, bool) { sum += t.energy_now(world); });
    return sum;
}

bool StepOperator::any_beside(const World& world) const {
    bool any = false;
    in_order(terms, world, [](const StepTerm& t) { return t.beside_assembly(); }, [&](StepTerm&, bool) { any = true; });
    return any;
}

bool StepOperator::add_beside_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out, double scale,
                                      const Eigen::VectorXd& mask) const {
    bool any = false;
    Eigen::VectorXd own;
    in_order(terms, world, [](const StepTerm& t) { return t.beside_assembly(); }, [&](StepTerm& t, bool) {
        t.product(world, p.cwiseProduct(mask), own, true);
        out += scale * own.cwiseProduct(mask);
        any = true;
    });
    return any;
}

BesideBlock StepOperator::jump_blocks(const World& world) const {
    BesideBlock out;
    in_order(terms, world, [](const StepTerm& t) { return t.gives_jump_block(); }, [&](StepTerm& t, bool) { t.jump_block(world, out); });
    return out;
}

uint64_t StepOperator::jump_version(const World& world) const {
    uint64_t out = 0;
    in_order(terms, world, [](const StepTerm& t) { return t.gives_jump_block(); },
             [&](StepTerm& t, bool) { out = out * 1000003u + t.jump_version(world) + 1u; });
    return out;
}

StepTerm* StepOperator::block_term(const World& world) const {
    StepTerm* one = nullptr;
    int count = 0;
    in_order(terms, world, [](const StepTerm& t) { return t.beside_assembly(); }, [&](StepTerm& t, bool) {
        one = &t;
        ++count;
    });
    return count == 1 && one->gives_beside_block() ? one : nullptr;
}

}  // namespace xcut
