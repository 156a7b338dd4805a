#pragma once
// The crack tips' condensed term checked against its own force (tests of systems/cut/crack_tip_system.h).
#include <Eigen/Core>
#include <random>

#include "engine/world.h"
#include "systems/pipeline.h"
#include "systems/step_term.h"

namespace xcut::testing {

struct TipTermCheck {
    double mismatch = 1.0;  ///< |fd - K p| / |K p|: the product against a central difference of the forces
    double tip_share = 0.0; ///< |K0 p - K p| / |K p|: how much the tips change the product
};

/// Moves w's nodes randomly (1e-4 m; in the plane for a 2D mesh), linearizes the step's terms and
/// compares their stiffness product along a random direction with the central difference of their
/// forces (rotations frozen at the linearization), and with the product of the elastic term alone.
inline TipTermCheck check_tip_term(World& w, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1e-4, 1e-4);
    const double z = w.elements.dim == 3 ? 1.0 : 0.0;
    for (Vec3& x : w.nodes.position) x += Vec3(u(rng), u(rng), z * u(rng));
    const StepOperator op = xcut_step_terms();
    op.relinearize(w);
    Eigen::VectorXd p(3 * w.nodes.count());
    for (int i = 0; i < w.nodes.count(); ++i) p.segment<3>(3 * i) = Vec3(u(rng), u(rng), z * u(rng)) * 1e4;
    Eigen::VectorXd Kp;
    op.stiffness_product(w, p, Kp);
    Eigen::Map<Eigen::VectorXd> x(w.nodes.position[0].data(), p.size());
    const Eigen::VectorXd x0 = x;
    const double eps = 1e-9;
    x = x0 + eps * p;
    op.forces(w);
    const Eigen::VectorXd fp = w.forces.force;
    x = x0 - eps * p;
    op.forces(w);
    const Eigen::VectorXd fd = -(fp - w.forces.force) / (2 * eps);
    x = x0;
    StepOperator plain{{op.terms[0]}};
    Eigen::VectorXd K0p;
    plain.stiffness_product(w, p, K0p);
    return {(fd - Kp).norm() / Kp.norm(), (K0p - Kp).norm() / Kp.norm()};
}

}  // namespace xcut::testing
