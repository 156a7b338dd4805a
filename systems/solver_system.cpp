#include "systems/solver_system.h"

#include <stdexcept>

#include "engine/parallel.h"
#include "systems/collision_system.h"
#include "systems/force_system.h"

namespace xcut {

Eigen::VectorXd free_mask(const World& world) {
    const Nodes& nodes = world.nodes;
    Eigen::VectorXd mask(3 * nodes.count());
    for (int i = 0; i < nodes.count(); ++i)
        for (int k = 0; k < 3; ++k) mask[3 * i + k] = (nodes.fixed[i] >> k) & 1 ? 0.0 : 1.0;
    return mask;
}

void project_constraints(const World& world, Eigen::Ref<Eigen::VectorXd> v) {
    const Nodes& nodes = world.nodes;
    for (int i = 0; i < nodes.count(); ++i)
        for (int k = 0; k < 3; ++k)
            if ((nodes.fixed[i] >> k) & 1) v[3 * i + k] = 0.0;
}

namespace {

/// rhs = h f(x_n + h v_k) - h beta K_k v_k - h alpha M v_k - M (v_k - v_n): minus the implicit Euler
/// residual at velocity v_k, with forces, rotations and K_k at x_k = x_n + h v_k (already computed).
/// Contacts are held at their start-of-step linearization: f_c0 - K_c (x_k - x_n).
Eigen::VectorXd newton_rhs(World& w, const Eigen::VectorXd& m3, const Eigen::VectorXd& vn, const Eigen::VectorXd& vk,
                           const Eigen::VectorXd& contact_force) {
    const SolverSettings& s = w.solver;
    const double h = s.dt;
    Eigen::VectorXd kv;
    stiffness_product(w, vk, kv);  // K_el + K_c
    Eigen::VectorXd rhs = h * (w.forces.force + contact_force) - h * s.damping_stiffness * kv -
                          h * s.damping_mass * m3.cwiseProduct(vk) - m3.cwiseProduct(vk - vn);
    if (w.contacts.count() > 0) {  // contact stiffness times the step's displacement h v_k
        Eigen::VectorXd kc = Eigen::VectorXd::Zero(vk.size());
        add_contact_stiffness_product(w, vk, kc);
        rhs -= h * h * kc;
    }
    return rhs;
}

}  // namespace

void implicit_euler_step(World& world) {
    Nodes& nodes = world.nodes;
    const SolverSettings& s = world.solver;
    const int n3 = 3 * nodes.count();
    const double h = s.dt;
    const double mass_scale = 1.0 + h * s.damping_mass;
    const double stiff_scale = h * h + h * s.damping_stiffness;

    Eigen::Map<Eigen::VectorXd> v(nodes.velocity[0].data(), n3);
    Eigen::Map<Eigen::VectorXd> x(nodes.position[0].data(), n3);
    Eigen::VectorXd m3(n3);
    for (int i = 0; i < nodes.count(); ++i) m3.segment<3>(3 * i).setConstant(nodes.mass[i]);

    Eigen::VectorXd kv;
    stiffness_product(world, v, kv);
    Eigen::VectorXd b = h * world.forces.force - stiff_scale * kv - h * s.damping_mass * m3.cwiseProduct(v);
    auto inverse_diagonal = [&] {
        return (mass_scale * m3 + stiff_scale * world.forces.stiffness_diagonal).cwiseInverse().eval();
    };
    Eigen::VectorXd inv_diag = inverse_diagonal();

    Eigen::VectorXd& dv = world.forces.last_dv;
    if (dv.size() != n3) dv.setZero(n3);
    auto apply = [&](const Eigen::VectorXd& p, Eigen::VectorXd& out) {
        stiffness_product(world, p, out);
        parallel_for(n3, [&](int i) { out[i] = mass_scale * m3[i] * p[i] + stiff_scale * out[i]; });
    };
    const Eigen::VectorXd mask = free_mask(world);
    CgResult cg = conjugate_gradient(apply, b, inv_diag, mask, s.cg_tolerance, s.cg_max_iterations, dv);
    const double start_energy = world.forces.elastic_energy;
    int newton = 1;
    if (s.newton_iterations > 1) {
        // Newton on the nonlinear step (rotations, forces and K re-evaluated at x_n + h v_k) until
        // |residual| <= newton_tolerance |residual at v_n|: the converged step is backward Euler
        // itself, which the once-linearized step only approximates (it gains energy on large
        // rotations at large dt: docs/verification.md problem 9).
        const Eigen::VectorXd xn = x, vn = v;
        Eigen::VectorXd contact_force = world.forces.force;  // f at x_n, contacts included ...
        compute_forces(world);
        contact_force -= world.forces.force;  // ... less elastic + gravity: the contact part
        const double r0 = std::sqrt(deterministic_dot(b.cwiseProduct(mask), b.cwiseProduct(mask)));
        Eigen::VectorXd vk = vn + dv;
        for (; newton < s.newton_iterations; ++newton) {
            project_constraints(world, vk);
            x = xn + h * vk;
            update_rotations(world);
            compute_forces(world);
            b = newton_rhs(world, m3, vn, vk, contact_force);
            const double r = std::sqrt(deterministic_dot(b.cwiseProduct(mask), b.cwiseProduct(mask)));
            if (!(r > s.newton_tolerance * r0)) break;
            inv_diag = inverse_diagonal();
            Eigen::VectorXd delta = Eigen::VectorXd::Zero(n3);
            const CgResult step = conjugate_gradient(apply, b, inv_diag, mask, s.cg_tolerance, s.cg_max_iterations, delta);
            cg.iterations += step.iterations;
            vk += delta;
        }
        x = xn;
        dv = vk - vn;
    }
    v += dv;
    project_constraints(world, v);
    x += h * v;

    world.time += h;
    ++world.step;
    StepMetrics& m = world.metrics.current;
    m.step = world.step;
    m.time = world.time;
    m.dt = h;
    m.cg_iterations = cg.iterations;
    m.cg_residual = cg.relative_residual;
    m.newton_iterations = newton;
    m.dofs = static_cast<int>(mask.sum());
    m.elastic_energy = start_energy;
    m.kinetic_energy = 0.5 * deterministic_sum(n3, [&](int i) { return m3[i] * v[i] * v[i]; });
    m.gravity_work = deterministic_sum(nodes.count(), [&](int i) {
        return nodes.mass[i] * world.gravity.dot(nodes.position[i] - nodes.rest[i]);
    });
}

StaticResult static_solve(World& world, double tolerance, int max_newton, double cg_tolerance,
                          int cg_max_iterations, const Eigen::VectorXd& load) {
    const int n3 = 3 * world.nodes.count();
    Eigen::Map<Eigen::VectorXd> x(world.nodes.position[0].data(), n3);
    const Eigen::VectorXd mask = free_mask(world);
    if (load.size() != 0 && load.size() != n3)
        throw std::invalid_argument("static_solve: the load needs 3 entries per DOF node");
    StaticResult result;
    double f0 = -1.0;
    for (; result.newton_iterations < max_newton; ++result.newton_iterations) {
        update_rotations(world);
        compute_forces(world);
        if (load.size() > 0) world.forces.force += load;
        const Eigen::VectorXd f = world.forces.force.cwiseProduct(mask);
        const double fnorm = std::sqrt(deterministic_dot(f, f));
        if (f0 < 0.0) f0 = fnorm;
        result.residual = f0 > 0.0 ? fnorm / f0 : 0.0;
        if (fnorm <= tolerance * f0 || fnorm == 0.0) {
            result.converged = true;
            break;
        }
        Eigen::VectorXd dx = Eigen::VectorXd::Zero(n3);
        const Eigen::VectorXd inv_diag = world.forces.stiffness_diagonal.cwiseMax(1e-300).cwiseInverse();
        auto apply = [&](const Eigen::VectorXd& p, Eigen::VectorXd& out) { stiffness_product(world, p, out); };
        result.cg_iterations +=
            conjugate_gradient(apply, f, inv_diag, mask, cg_tolerance, cg_max_iterations, dx).iterations;
        x += dx;
    }
    return result;
}

SystemDesc solver_system() {
    return {"SolverSystem", kNodes | kElements | kForces, kNodes, implicit_euler_step};
}

}  // namespace xcut
