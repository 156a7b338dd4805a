#include "systems/solver/solver_system.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "engine/error.h"
#include "engine/parallel.h"
#include "systems/solver/energy_check.h"
#include "systems/solver/linear_assembly.h"
#include "systems/solver/linear_solver.h"

namespace xcut {

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
Eigen::VectorXd newton_rhs(World& w, const StepOperator& op, double h, const Eigen::VectorXd& m3, const Eigen::VectorXd& vn,
                           const Eigen::VectorXd& vk, const Eigen::VectorXd& held_force) {
    const SolverSettings& s = w.solver;
    Eigen::VectorXd kv;
    op.stiffness_product(w, vk, kv);  // every term's K
    Eigen::VectorXd rhs = h * (w.forces.force + held_force) - h * s.damping_stiffness * kv -
                          h * s.damping_mass * m3.cwiseProduct(vk) - m3.cwiseProduct(vk - vn);
    if (op.any_held(w)) {  // the held terms' stiffness times the step's displacement h v_k
        Eigen::VectorXd kc = Eigen::VectorXd::Zero(vk.size());
        op.add_held_product(w, vk, kc);
        rhs -= h * h * kc;
    }
    return rhs;
}

/// The held terms' part of the forces at the step's start (the contacts'): forces as the systems left
/// them, less those of the other terms recomputed at the same state (which this leaves in place).
Eigen::VectorXd held_part(World& w, const StepOperator& op) {
    Eigen::VectorXd held = w.forces.force;
    op.forces(w);
    held -= w.forces.force;
    return held;
}

/// What a step changes, to start it again in substeps.
struct StepStart {
    std::vector<Vec3> position, velocity;
    std::vector<Mat3> rotation;
    Eigen::VectorXd force, stiffness_diagonal, last_dv;
    double elastic_energy = 0.0;
};

StepStart save_step(const World& w) {
    return {w.nodes.position, w.nodes.velocity, w.elements.rotation, w.forces.force, w.forces.stiffness_diagonal,
            w.forces.last_dv, w.forces.elastic_energy};
}

void restore_step(World& w, const StepStart& s) {
    w.nodes.position = s.position, w.nodes.velocity = s.velocity, w.elements.rotation = s.rotation;
    w.forces.force = s.force, w.forces.stiffness_diagonal = s.stiffness_diagonal, w.forces.last_dv = s.last_dv;
    w.forces.elastic_energy = s.elastic_energy;
}

/// The energy of the step's start (energy_check.h): its stored part as the step's forces counted it.
StepEnergy start_energy(const World& world, const Eigen::VectorXd& m3) {
    const int n3 = 3 * world.nodes.count();
    StepEnergy e = motion_energy(world, m3, Eigen::Map<const Eigen::VectorXd>(world.nodes.velocity[0].data(), n3));
    e.stored = world.forces.elastic_energy;
    return e;
}

/// Whether a step of length h that changes the velocities by dv gains energy (energy_check.h): the
/// energy at its end, the stored part with rotations taken from the end positions, against its
/// start's and the held terms' work over it. Changes nothing it does not restore.
bool step_gains(World& world, const StepOperator& op, double h, const Eigen::VectorXd& m3, const Eigen::VectorXd& dv) {
    const int n3 = 3 * world.nodes.count();
    Eigen::Map<Eigen::VectorXd> x(world.nodes.position[0].data(), n3);
    Eigen::VectorXd v1 = Eigen::Map<const Eigen::VectorXd>(world.nodes.velocity[0].data(), n3) + dv;
    project_constraints(world, v1);
    const Eigen::VectorXd dx = h * v1;
    double work = 0.0;
    if (op.any_held(world)) {  // f_h0 . dx - dx . K_h dx / 2
        Eigen::VectorXd kdx = Eigen::VectorXd::Zero(n3);
        op.add_held_product(world, dx, kdx);
        work = deterministic_dot(world.forces.held_force, dx) - 0.5 * deterministic_dot(dx, kdx);
    }
    const StepEnergy before = start_energy(world, m3);
    const Eigen::VectorXd xn = x;
    x += dx;
    StepEnergy after = motion_energy(world, m3, v1);
    after.stored = op.energy_now(world);
    x = xn;
    return gained_energy(before, after, work);
}

/// One backward Euler step of length h from the current state, forces and rotations (paper §4.3):
/// the linearized solve, then Newton iterations when asked or, where the linearized step gained
/// energy, solver.newton.on_energy_gain of them (systems/solver/energy_check.h; the step's start
/// is then saved in `start` if it is not yet, as the iterations move rotations and forces). Commits
/// v and x only if every solve converged; returns the solves' sum.
LinearSolve euler_substep(World& world, const StepOperator& op, double h, const Eigen::VectorXd& m3,
                          const Eigen::VectorXd& mask, std::optional<StepStart>& start) {
    Nodes& nodes = world.nodes;
    const SolverSettings& s = world.solver;
    const int n3 = 3 * nodes.count();
    const StepScales scales = step_scales(s, h);
    const double mass_scale = scales.mass, stiff_scale = scales.stiffness;
    Eigen::Map<Eigen::VectorXd> v(nodes.velocity[0].data(), n3);
    Eigen::Map<Eigen::VectorXd> x(nodes.position[0].data(), n3);

    // b = h f - (h^2 + h beta) K v - h alpha M v. With A assembled, and v 0 on the held axes (A's
    // held rows and columns are filtered), that is h f + M v - A v on the free rows (CG masks the
    // others): one block product instead of the matrix-free K v.
    const StepMatrix filled = fill_step_matrix(world, op, mass_scale, stiff_scale);
    Eigen::VectorXd b, kv;
    if (filled.assembled && (v.array() * (1.0 - mask.array()) == 0.0).all()) {
        linear_multiply(world.linear, v, kv);
        op.add_beside_product(world, v, kv, stiff_scale, mask);
        b = h * world.forces.force + m3.cwiseProduct(v) - kv;
    } else {
        op.stiffness_product(world, v, kv);
        b = h * world.forces.force - stiff_scale * kv - h * s.damping_mass * m3.cwiseProduct(v);
    }
    Eigen::VectorXd dv = world.forces.last_dv.size() == n3 ? world.forces.last_dv : Eigen::VectorXd::Zero(n3);
    LinearSolve total = solve_step_linear(world, op, mass_scale, stiff_scale, b, mask, dv, &filled);
    int newton = 1, iterations = s.newton_iterations;
    // The held terms' work needs their start force (the systems that add them keep it, unless a
    // caller other than the pipeline applied them).
    const bool held_known = !op.any_held(world) || world.forces.held_force.size() == n3;
    if (total.converged && iterations == 1 && s.newton_on_energy_gain > 1 && held_known && step_gains(world, op, h, m3, dv)) {
        iterations = s.newton_on_energy_gain;
        ++world.metrics.energy_newton_steps;
        if (!start) start = save_step(world);
    }
    if (total.converged && iterations > 1) {
        // Newton on the nonlinear step (rotations, forces and K re-evaluated at x_n + h v_k) until
        // |residual| <= newton_tolerance |residual at v_n|: the converged step is backward Euler
        // itself, which the once-linearized step only approximates (it gains energy on large
        // rotations at large dt: docs/verification.md problem 9).
        const Eigen::VectorXd xn = x, vn = v;
        const Eigen::VectorXd held_force = held_part(world, op);
        const double r0 = std::sqrt(deterministic_dot(b.cwiseProduct(mask), b.cwiseProduct(mask)));
        Eigen::VectorXd vk = vn + dv;
        for (; newton < iterations && total.converged; ++newton) {
            project_constraints(world, vk);
            x = xn + h * vk;
            op.relinearize(world);
            b = newton_rhs(world, op, h, m3, vn, vk, held_force);
            const double r = std::sqrt(deterministic_dot(b.cwiseProduct(mask), b.cwiseProduct(mask)));
            if (!(r > s.newton_tolerance * r0)) break;
            Eigen::VectorXd delta = Eigen::VectorXd::Zero(n3);
            const LinearSolve step = solve_linear(world, op, mass_scale, stiff_scale, b, mask, delta);
            total.cg.iterations += step.cg.iterations;
            total.cg.relative_residual = step.cg.relative_residual;
            total.converged = step.converged;
            total.refactored = total.refactored || step.refactored;
            vk += delta;
        }
        x = xn;
        dv = vk - vn;
    }
    world.metrics.current.newton_iterations = newton;
    if (!total.converged) return total;
    world.forces.last_dv = dv;
    v += dv;
    project_constraints(world, v);
    x += h * v;
    return total;
}

/// The step in `substeps` equal parts; false as soon as one part's solve fails.
bool run_substeps(World& world, const StepOperator& op, int substeps, const Eigen::VectorXd& m3,
                  const Eigen::VectorXd& mask, const Eigen::VectorXd& held_force, LinearSolve& total,
                  std::optional<StepStart>& start) {
    const double h = world.solver.dt / substeps;
    total = LinearSolve{};
    for (int k = 0; k < substeps; ++k) {
        if (k > 0) {  // forces and rotations at the substep's start; held terms as linearized at the step's
            op.relinearize(world);
            world.forces.force += held_force;
        }
        const LinearSolve part = euler_substep(world, op, h, m3, mask, start);
        total.cg.iterations += part.cg.iterations;
        total.cg.relative_residual = std::isnan(part.cg.relative_residual)
                                         ? part.cg.relative_residual
                                         : std::max(total.cg.relative_residual, part.cg.relative_residual);
        total.refactored = total.refactored || part.refactored;
        total.converged = part.converged;
        if (!part.converged) return false;
    }
    return true;
}

[[noreturn]] void fail_step(const World& w, const LinearSolve& last, int substeps) {
    const SolverSettings& s = w.solver;
    const std::string where = fmt::format("step {} (from t = {:.6g} s, dt {:.3g} s)", w.step + 1, w.time, s.dt);
    if (!std::isfinite(last.cg.relative_residual))
        throw NumericalError(fmt::format(
            "{}: the linear system holds NaN or infinite values (forces, stiffness or the state), even in {} "
            "substeps. Change: Young's modulus, density or gravity to physical values (SI units: Pa, kg/m^3, m/s^2)",
            where, substeps));
    throw NumericalError(fmt::format(
        "{}: the linear solve ({}) stopped at relative residual {:.3g} after {} CG iterations, above the tolerance "
        "{:.3g}, even with a fresh factor and in {} substeps of {:.3g} s. Change: a smaller solver.dt, a larger "
        "solver.cg_max_iterations (now {}), solver.linear \"cholesky\", or the material ({})",
        where, w.linear.method, last.cg.relative_residual, last.cg.iterations, s.cg_tolerance, substeps,
        s.dt / substeps, s.cg_max_iterations,
        w.quadratic.count() > 0 ? "a Poisson ratio near 0.5 makes the system ill-conditioned: the matrix-free jacobi "
                                  "method needs thousands of iterations there"
                                : "a Poisson ratio near 0.5 locks linear tetrahedra: \"element\": \"quadratic\" where "
                                  "the tissue is not cut"));
}

}  // namespace

void implicit_euler_step(World& world, const StepOperator& op) {
    Nodes& nodes = world.nodes;
    const SolverSettings& s = world.solver;
    const int n3 = 3 * nodes.count();
    Eigen::VectorXd m3(n3);
    for (int i = 0; i < nodes.count(); ++i) m3.segment<3>(3 * i).setConstant(nodes.mass[i]);
    const Eigen::VectorXd mask = free_mask(world);
    op.add_start_forces(world);  // the terms no system computes (crack tips) join the step's force
    const double start_energy = world.forces.elastic_energy;

    // A solve above its tolerance is not accepted: solve_linear renews a stale factor first; then
    // the step is split in 2, 4, ... up to solver.max_substeps parts; then the run stops (fail_step).
    // A failed single step commits nothing, so the step's start is saved only when it is needed:
    // up front only if Newton iterations move rotations and forces on the way.
    std::optional<StepStart> start;
    if (s.newton_iterations > 1) start = save_step(world);
    world.linear.step_preconditioner = 0, world.linear.step_wait_ms = 0.0;  // the solves below say what they did
    Eigen::VectorXd held_force;
    LinearSolve total;
    int substeps = 1;
    while (!run_substeps(world, op, substeps, m3, mask, held_force, total, start)) {
        if (2 * substeps > s.max_substeps) fail_step(world, total, substeps);
        if (!start) start = save_step(world);
        restore_step(world, *start);
        // Newton iterations and substeps linearized the terms elsewhere (the crack tips' factor is
        // made at the rotations of its linearization): again at the step's start.
        op.linearize(world);
        if (held_force.size() == 0) {
            held_force = op.any_held(world) ? held_part(world, op) : Eigen::VectorXd::Zero(n3);
            restore_step(world, *start);
        }
        substeps *= 2;
    }

    world.time += s.dt;
    ++world.step;
    op.finish_step(world);
    Metrics& metrics = world.metrics;
    StepMetrics& m = metrics.current;
    m.step = world.step;
    m.time = world.time;
    m.dt = s.dt;
    m.cg_iterations = total.cg.iterations;
    m.cg_residual = total.cg.relative_residual;
    m.solve_flag = substeps > 1 ? 2 : total.refactored ? 1 : 0;
    m.substeps = substeps;
    m.preconditioner = world.linear.step_preconditioner;
    m.preconditioner_wait_ms = world.linear.step_wait_ms;
    metrics.refactored_steps += m.solve_flag == 1;
    metrics.substepped_steps += substeps > 1;
    metrics.max_substeps = std::max(metrics.max_substeps, substeps);
    m.dofs = static_cast<int>(mask.sum());
    m.elastic_energy = start_energy;
    Eigen::Map<Eigen::VectorXd> v(nodes.velocity[0].data(), n3);
    m.kinetic_energy = 0.5 * deterministic_sum(n3, [&](int i) { return m3[i] * v[i] * v[i]; });
    m.gravity_work = deterministic_sum(nodes.count(), [&](int i) {
        return nodes.mass[i] * world.gravity.dot(nodes.position[i] - nodes.rest[i]);
    });
}

StaticResult static_solve(World& world, const StepOperator& op, double tolerance, int max_newton, double cg_tolerance,
                          int cg_max_iterations, const Eigen::VectorXd& load) {
    const int n3 = 3 * world.nodes.count();
    Eigen::Map<Eigen::VectorXd> x(world.nodes.position[0].data(), n3);
    const Eigen::VectorXd mask = free_mask(world);
    if (load.size() != 0 && load.size() != n3)
        throw std::invalid_argument("static_solve: the load needs 3 entries per DOF node");
    StaticResult result;
    double f0 = -1.0;
    // Newton also stops when a solve moved the free nodes by less than kRoundOffUpdate of
    // their displacement: the residual is then at its round-off floor, which at small strains can
    // lie above `tolerance` (the edge-cracked plate at strain 1e-6: 7e-7 of the load at 155k DOFs,
    // 2e-6 at 618k, where CMOD moved by 6e-9 relative over 28 further iterations).
    constexpr double kRoundOffUpdate = 1e-9;
    double last_update = 1.0;
    const Eigen::Map<const Eigen::VectorXd> rest(world.nodes.rest[0].data(), n3);
    for (; result.newton_iterations < max_newton; ++result.newton_iterations) {
        op.relinearize(world);
        if (load.size() > 0) world.forces.force += load;
        const Eigen::VectorXd f = world.forces.force.cwiseProduct(mask);
        const double fnorm = std::sqrt(deterministic_dot(f, f));
        if (f0 < 0.0) f0 = fnorm;
        result.residual = f0 > 0.0 ? fnorm / f0 : 0.0;
        if (fnorm <= tolerance * f0 || fnorm == 0.0 || last_update <= kRoundOffUpdate) {
            result.converged = true;
            result.at_round_off = fnorm > tolerance * f0 && fnorm > 0.0;
            break;
        }
        // K dx = f by the scene's linear method (A = 0 M + 1 K), at the caller's tolerance and cap.
        Eigen::VectorXd dx = Eigen::VectorXd::Zero(n3);
        const LinearSolve solve = solve_linear(world, op, 0.0, 1.0, f, mask, dx, CgLimits{cg_tolerance, cg_max_iterations});
        result.cg_iterations += solve.cg.iterations;
        x += dx;
        const Eigen::VectorXd u = (x - rest).cwiseProduct(mask);
        const double unorm = std::sqrt(deterministic_dot(u, u));
        // At the floor the right-hand side is round-off, which CG cannot reduce to its tolerance; a
        // solve that reduced it at all (half) counts, one that broke down (dx = 0) does not.
        const bool progressed = solve.cg.relative_residual < 0.5;
        last_update = progressed && unorm > 0.0 ? std::sqrt(deterministic_dot(dx, dx)) / unorm : 1.0;
    }
    op.finish_step(world);  // what the terms keep of the final state (the crack tips' amplitudes)
    return result;
}

SystemDesc solver_system(const World& world, std::shared_ptr<const StepOperator> op) {
    // Resolved once where the solver was prepared (auto's fill estimate is a symbolic analysis).
    std::string why = world.linear.method_why;
    const std::string method = why.empty() ? resolve_linear_method(world, &why) : world.linear.method;
    // Writes the state, the step's forces and linear system, the rotations (Newton iterations and
    // substeps relinearize) and the step's metrics.
    SystemDesc s{"SolverSystem", kNodes | kElements | kForces, kNodes | kElements | kForces | kLinear | kMetrics,
                 [op](World& w) { implicit_euler_step(w, *op); }, "linear: " + method + " (" + why + ")"};
    // the terms' stiffness, the held contacts, the tools' work (the energy check)
    return s.also_reads(kMaterials | kContacts | kGravity | kTools | kGrasps);
}

}  // namespace xcut
