#include "systems/step_term.h"

namespace xcut {

void StepOperator::linearize(World& world) const {
    for (const auto& t : terms) t->linearize(world);
}

void StepOperator::relinearize(World& world) const {
    linearize(world);
    forces(world);
}

void StepOperator::forces(World& world) const {
    bool first = true;
    for (const auto& t : terms)
        if (!t->held() && t->active(world)) {
            t->force(world, first);
            first = false;
        }
}

void StepOperator::stiffness_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const {
    bool first = true;
    for (const auto& t : terms)
        if (t->active(world)) {
            t->product(world, p, out, first);
            first = false;
        }
}

void StepOperator::stiffness_product_in_team(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const {
    bool first = true;
    for (const auto& t : terms)
        if (t->active(world)) {
            t->product_in_team(world, p, out, first);
            first = false;
        }
}

void StepOperator::prepare_product(World& world) const {
    for (const auto& t : terms) t->prepare_product(world);
}

void StepOperator::add_held_product(World& world, const Eigen::VectorXd& p, Eigen::VectorXd& out) const {
    for (const auto& t : terms)
        if (t->held() && t->active(world)) t->product(world, p, out, false);
}

bool StepOperator::any_held(const World& world) const {
    for (const auto& t : terms)
        if (t->held() && t->active(world)) return true;
    return false;
}

}  // namespace xcut
