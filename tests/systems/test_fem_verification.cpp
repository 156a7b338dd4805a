// docs/verification.md problems 1 (patch test) and 2 (rigid-motion invariance) for the corotational
// linear element on tetrahedra and on triangles (plane stress).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "systems/kernels/corotational_kernel.h"
#include "systems/force_system.h"
#include "systems/solver/solver_system.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::grid;
using testing::world_from_mesh;

bool on_boundary(const Vec3& p, const Vec3& size, int dims) {
    for (int k = 0; k < dims; ++k)
        if (std::abs(p[k]) < 1e-12 || std::abs(p[k] - size[k]) < 1e-12) return true;
    return false;
}

/// Patch test (docs/verification.md problem 1): boundary nodes displaced by u = A X + c, interior free; the
/// static solution is that field everywhere (relative 1e-10) with one constant stress.
void run_patch_test(World world, const Vec3& size, int dims) {
    Eigen::Matrix3d A;
    A << 2e-3, -1e-3, 5e-4, 7e-4, -1.5e-3, 1e-3, -4e-4, 8e-4, 1.2e-3;
    if (dims == 2) A.row(2).setZero(), A.col(2).setZero();
    const Vec3 c(1e-4, -2e-4, dims == 3 ? 3e-4 : 0.0);
    auto field = [&](const Vec3& X) -> Vec3 { return A * X + c; };
    Nodes& n = world.nodes;
    int interior = 0;
    for (int i = 0; i < n.count(); ++i) {
        if (on_boundary(n.rest[i], size, dims)) {
            world.constraints.nodes.push_back(i);
            n.position[i] = n.rest[i] + field(n.rest[i]);
        } else {
            ++interior;
        }
    }
    ASSERT_GT(interior, 3);
    apply_constraints(world);
    const StaticResult r = static_solve(world, xcut_step_terms(), 1e-12, 50, 1e-14, 5000);
    EXPECT_TRUE(r.converged) << "residual " << r.residual;

    double max_u = 0.0, max_err = 0.0;
    for (int i = 0; i < n.count(); ++i) {
        const Vec3 u = field(n.rest[i]);
        max_u = std::max(max_u, u.norm());
        max_err = std::max(max_err, (n.position[i] - n.rest[i] - u).norm());
    }
    EXPECT_LT(max_err / max_u, 1e-10) << "max error " << max_err << " m";

    // Stress (here the corotated strain, which stress is linear in) is one constant tensor.
    update_rotations(world);
    const Elements& el = world.elements;
    auto strain = [&](int e) -> Mat3 {
        std::array<Vec3, 4> x;
        for (int a = 0; a < el.nodes_per_element(); ++a) x[a] = n.position[el.nodes[e][a]];
        Mat3 F = Mat3::Identity();
        if (dims == 3) {
            F = edge_matrix<3>(x) * el.dm_inv[e];
        } else {
            F.topLeftCorner<2, 2>() = edge_matrix<2>(x) * el.dm_inv[e].topLeftCorner<2, 2>();
        }
        const Mat3 H = el.rotation[e].transpose() * F - Mat3::Identity();
        return 0.5 * (H + H.transpose());
    };
    const Mat3 eps0 = strain(0);
    for (int e = 1; e < el.count(); ++e) EXPECT_LT((strain(e) - eps0).norm(), 1e-10 * eps0.norm()) << "element " << e;
}

TEST(PatchTest, IrregularTetrahedra) {
    const Vec3 size(1.0, 0.8, 0.6);
    run_patch_test(world_from_mesh(generate_box(grid(size, {4, 4, 3}, 0.25, 11))), size, 3);
}

TEST(PatchTest, IrregularTrianglesPlaneStress) {
    const Vec3 size(1.0, 0.7, 0.0);
    run_patch_test(world_from_mesh(generate_plate(grid(size, {6, 5, 1}, 0.3, 5))), size, 2);
}

// Newton stops at the round-off floor: with a tolerance no residual reaches, it ends once a converged
// solve moves the nodes by less than 1e-9 of their displacement, says so, and holds the answer of a
// reachable tolerance.
TEST(StaticSolve, StopsAtTheRoundOffFloor) {
    Material stiff;
    stiff.young = 1e9;  // sag ~1e-7 of the length: small rotations, Newton converges in a few steps
    auto sag = [&](double tolerance, StaticResult& r) {
        World w = world_from_mesh(generate_box(grid({0.04, 0.01, 0.01}, {8, 2, 2}, 0.2, 3)), stiff);
        w.gravity = Vec3(0, 0, -9.81);
        w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
        apply_constraints(w);
        r = static_solve(w, xcut_step_terms(), tolerance, 30, 1e-12, 5000);
        return w.nodes.position;
    };
    StaticResult reachable, floor;
    const auto a = sag(1e-6, reachable), b = sag(1e-30, floor);
    ASSERT_TRUE(reachable.converged);
    EXPECT_FALSE(reachable.at_round_off);
    EXPECT_TRUE(floor.converged);
    EXPECT_TRUE(floor.at_round_off);
    EXPECT_LT(floor.newton_iterations, 30);
    EXPECT_GT(floor.residual, 1e-30);
    double worst = 0.0, largest = 0.0;
    const World reference = world_from_mesh(generate_box(grid({0.04, 0.01, 0.01}, {8, 2, 2}, 0.2, 3)));
    for (size_t i = 0; i < a.size(); ++i) {
        worst = std::max(worst, (a[i] - b[i]).norm());
        largest = std::max(largest, (a[i] - reference.nodes.rest[i]).norm());
    }
    EXPECT_LT(worst, 1e-6 * largest);
}

Mat3 rotation_about(const Vec3& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).matrix(); }

/// Rigid-motion invariance (docs/verification.md problem 2): energy unchanged and forces rotated under a rigid
/// motion of a deformed body; zero force for a rigid motion of the rest shape.
TEST(RigidMotion, TetrahedraEnergyAndForcesInvariant) {
    World world = world_from_mesh(generate_box(grid({0.03, 0.02, 0.01}, {4, 3, 2}, 0.2, 3)));
    std::mt19937_64 rng(9);
    std::normal_distribution<double> noise(0.0, 5e-4);
    Nodes& n = world.nodes;
    for (int i = 0; i < n.count(); ++i) n.position[i] = n.rest[i] + Vec3(noise(rng), noise(rng), noise(rng));
    update_rotations(world);
    compute_forces(world);
    const Eigen::VectorXd f0 = world.forces.force;
    const double W0 = world.forces.elastic_energy;
    ASSERT_GT(W0, 0.0);

    const Mat3 Q = rotation_about(Vec3(1, 2, 3), 2.1);
    const Vec3 t(0.5, -0.2, 0.1);
    for (auto& x : n.position) x = Q * x + t;
    update_rotations(world);
    compute_forces(world);
    EXPECT_NEAR(world.forces.elastic_energy, W0, 1e-10 * W0);
    double fmax = f0.cwiseAbs().maxCoeff();
    for (int i = 0; i < n.count(); ++i)
        EXPECT_LT((world.forces.force.segment<3>(3 * i) - Q * f0.segment<3>(3 * i)).norm(), 1e-9 * fmax);

    // Rest shape moved rigidly: no force, no energy.
    for (int i = 0; i < n.count(); ++i) n.position[i] = Q * n.rest[i] + t;
    update_rotations(world);
    compute_forces(world);
    const double scale = world.materials.list[0].young * 0.01 * 0.01;  // E h^2: a force scale [N]
    EXPECT_LT(world.forces.force.cwiseAbs().maxCoeff(), 1e-10 * scale);
    EXPECT_LT(world.forces.elastic_energy, 1e-20);
}

TEST(RigidMotion, TrianglesInPlaneRotation) {
    World world = world_from_mesh(generate_plate(grid({0.05, 0.03, 0}, {5, 3, 1}, 0.2, 4)));
    Nodes& n = world.nodes;
    std::mt19937_64 rng(2);
    std::normal_distribution<double> noise(0.0, 4e-4);
    for (int i = 0; i < n.count(); ++i) n.position[i] = n.rest[i] + Vec3(noise(rng), noise(rng), 0.0);
    update_rotations(world);
    compute_forces(world);
    const Eigen::VectorXd f0 = world.forces.force;
    const double W0 = world.forces.elastic_energy;
    const Mat3 Q = rotation_about(Vec3::UnitZ(), -2.5);
    for (auto& x : n.position) x = Q * x + Vec3(0.3, 0.1, 0.0);
    update_rotations(world);
    compute_forces(world);
    EXPECT_NEAR(world.forces.elastic_energy, W0, 1e-10 * W0);
    const double fmax = f0.cwiseAbs().maxCoeff();
    for (int i = 0; i < n.count(); ++i)
        EXPECT_LT((world.forces.force.segment<3>(3 * i) - Q * f0.segment<3>(3 * i)).norm(), 1e-9 * fmax);
    for (int i = 0; i < n.count(); ++i) n.position[i] = Q * n.rest[i];
    update_rotations(world);
    compute_forces(world);
    EXPECT_LT(world.forces.force.cwiseAbs().maxCoeff(), 1e-10 * world.materials.list[0].young * 0.01 * 1e-3);
}

}  // namespace
}  // namespace xcut
