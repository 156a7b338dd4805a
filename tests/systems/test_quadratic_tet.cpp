// The quadratic tetrahedron (systems/kernels/quadratic_tet.h): its integrals against closed forms, its
// rigid-motion invariance, the agreement of its force, product, blocks and diagonal, its HRZ masses;
// in a world: the linear patch test, the assembled and matrix-free solves, a clamped beam against
// beam theory, determinism, the meshes it refuses, and its visual surface's curvature.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "engine/io/generators.h"
#include "engine/parallel.h"
#include "engine/setup.h"
#include "systems/force_system.h"
#include "systems/kernels/quadratic_tet.h"
#include "systems/kernels/tet10_side_rule.h"
#include "systems/pipeline.h"
#include "systems/solver/linear_solver.h"
#include "systems/solver/solver_system.h"
#include "systems/surface/mapping_system.h"
#include "tests/systems/quadratic_fixtures.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::grid;

using testing::corners;
using testing::dm_inverse;
using testing::kLame;
using testing::nodes_of;
using testing::second_moment;
using testing::volume_of;

TEST(QuadraticTet, IntegratesTheEnergyOfQuadraticFieldsExactly) {
    const auto X = corners();
    const Tet10Vectors rest = nodes_of(X);
    const Tet10Gradients G = tet10_gradients(dm_inverse(X));
    const double k = 1e-2;
    // u = (k x^2, 0, 0): eps_xx = 2 k x, energy density (lambda/2 + mu) 4 k^2 x^2.
    Tet10Vectors x, f;
    for (int j = 0; j < 10; ++j) x[j] = rest[j] + Vec3(k * rest[j].x() * rest[j].x(), 0, 0);
    const double e1 = tet10_forces(x, G, Mat3::Identity(), volume_of(X), kLame, f);
    const double exact1 = (0.5 * kLame.lambda + kLame.mu) * 4.0 * k * k * second_moment(X, 0, 0);
    EXPECT_NEAR(e1, exact1, 1e-12 * exact1);
    // u = (0, k x z, 0): eps_xy = k z / 2, eps_yz = k x / 2, energy density mu k^2 (x^2 + z^2) / 2.
    for (int j = 0; j < 10; ++j) x[j] = rest[j] + Vec3(0, k * rest[j].x() * rest[j].z(), 0);
    const double e2 = tet10_forces(x, G, Mat3::Identity(), volume_of(X), kLame, f);
    const double exact2 = 0.5 * kLame.mu * k * k * (second_moment(X, 0, 0) + second_moment(X, 2, 2));
    EXPECT_NEAR(e2, exact2, 1e-12 * exact2);
}

TEST(QuadraticTet, RigidMotionGivesNoForceAndNoEnergy) {
    const auto X = corners();
    const Tet10Vectors rest = nodes_of(X);
    const Mat3 Q = Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
    Tet10Vectors x, f;
    for (int j = 0; j < 10; ++j) x[j] = Q * rest[j] + Vec3(0.3, -0.1, 0.2);
    // The element's R from the corner tetrahedron's F, as the ForceSystem takes it.
    const double e = tet10_forces(x, tet10_gradients(dm_inverse(X)), Q, volume_of(X), kLame, f);
    EXPECT_NEAR(e, 0.0, 1e-18);
    for (const Vec3& fj : f) EXPECT_LT(fj.norm(), 1e-10);
}

/// The constant-pressure law (P2-P0, LameParameters::lambda_mean): lambda on the mean dilatation only.
const LameParameters kLameMean{0.0, kLame.mu, kLame.lambda};

/// One rule's and law's force, product, blocks and diagonal agree; the force is minus the energy's
/// gradient; the stiffness is symmetric with the 6 rigid modes alone as zero-energy modes.
template <size_t P>
void expect_kernels_agree(const Tet10PointGradients<P>& G, double V, const LameParameters& lame) {
    const Tet10Vectors rest = nodes_of(corners());
    const Mat3 R = Eigen::AngleAxisd(0.3, Vec3(0.2, 1, -0.4).normalized()).toRotationMatrix();
    Tet10Vectors x, p, f0, f1, Kp;
    for (int j = 0; j < 10; ++j) {
        x[j] = R * rest[j] + 1e-3 * Vec3(std::sin(3.0 * j), std::cos(5.0 * j), std::sin(7.0 * j + 1));
        p[j] = Vec3(std::cos(2.0 * j + 1), std::sin(j + 0.5), std::cos(11.0 * j));
    }
    tet10_forces(x, G, R, V, lame, f0);
    Tet10Vectors xp = x, xm = x, unused;
    for (int j = 0; j < 10; ++j) xp[j] += p[j], xm[j] -= p[j];
    tet10_forces(xp, G, R, V, lame, f1);
    tet10_stiffness_product(p, G, R, V, lame, Kp);
    // At a frozen R the force is linear: f(x + p) - f(x) = -K p.
    double scale = 0.0;
    for (int j = 0; j < 10; ++j) scale = std::max(scale, Kp[j].norm());
    for (int j = 0; j < 10; ++j) EXPECT_LT((f1[j] - f0[j] + Kp[j]).norm(), 1e-10 * scale) << j;
    // The energy is quadratic in x at a frozen R: its central difference is exact, -2 f(x) . p.
    const double difference = tet10_forces(xp, G, R, V, lame, unused) - tet10_forces(xm, G, R, V, lame, unused);
    double work = 0.0;
    for (int j = 0; j < 10; ++j) work += f0[j].dot(p[j]);
    EXPECT_NEAR(difference, -2.0 * work, 1e-9 * std::abs(difference));
    // The 30 x 30 matrix from the blocks: its product, its diagonal, symmetry, 6 rigid modes.
    const Eigen::MatrixXd K = testing::tet10_matrix(G, R, V, lame);
    Eigen::VectorXd pv(30);
    for (int j = 0; j < 10; ++j) pv.segment<3>(3 * j) = p[j];
    const Eigen::VectorXd Kpv = K * pv;
    for (int j = 0; j < 10; ++j) EXPECT_LT((Kpv.segment<3>(3 * j) - Kp[j]).norm(), 1e-10 * scale) << j;
    EXPECT_LT((K - K.transpose()).norm(), 1e-10 * K.norm());
    Tet10Vectors diagonal;
    tet10_stiffness_diagonal(G, R, V, lame, diagonal);
    for (int j = 0; j < 10; ++j)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(diagonal[j][c], K(3 * j + c, 3 * j + c), 1e-10 * K.norm());
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
    for (int k = 0; k < 6; ++k) EXPECT_LT(std::abs(ev[k]), 1e-10 * ev[29]) << k;
    EXPECT_GT(ev[6], 1e-6 * ev[29]);  // no other zero-energy mode: the shear part is fully integrated
}

// Full integration and the constant pressure, over the whole element and over one side of a cut
// (a corner cut at 0.4 of its three edges).
TEST(QuadraticTet, ForceProductBlocksAndDiagonalAgree) {
    const auto X = corners();
    const Tet10Gradients G = tet10_gradients(dm_inverse(X));
    for (const LameParameters& lame : {kLame, kLameMean}) {
        SCOPED_TRACE(lame.lambda_mean);
        expect_kernels_agree(G, volume_of(X), lame);
    }
    std::array<double, 6> t{0.4, 0.4, 0.4, 0.0, 0.0, 0.0};
    for (int side : {1, -1}) {
        SCOPED_TRACE(side);
        const TetSideRule rule = tet_side_rule({1, -1, -1, -1}, t, side);
        expect_kernels_agree(tet10_side_gradients(dm_inverse(X), rule), volume_of(X), kLameMean);
    }
}

// The constant pressure's energy against its closed form: under u = (a x^2, 0, 0) the dilatation
// 2 a x has the element mean 2 a xbar (xbar: the corners' mean), so with lambda on the mean alone
// E = lambda V (2 a xbar)^2 / 2; full integration gives lambda/2 times the integral of (2 a x)^2,
// 2 lambda a^2 times the second moment (larger by the variance of x).
TEST(QuadraticTet, TheConstantPressuresEnergyIsItsMeanDilatationsClosedForm) {
    const auto X = corners();
    const Tet10Vectors rest = nodes_of(X);
    const Tet10Gradients G = tet10_gradients(dm_inverse(X));
    const double a = 0.3, lambda = 7.0e4, V = volume_of(X);
    Tet10Vectors x, f;
    for (int j = 0; j < 10; ++j) x[j] = rest[j] + Vec3(a * rest[j].x() * rest[j].x(), 0.0, 0.0);
    double xbar = 0.0;
    for (const Vec3& c : X) xbar += c.x() / 4.0;
    const double mean = tet10_forces(x, G, Mat3::Identity(), V, LameParameters{0.0, 0.0, lambda}, f);
    const double full = tet10_forces(x, G, Mat3::Identity(), V, LameParameters{lambda, 0.0}, f);
    EXPECT_NEAR(mean, 0.5 * lambda * V * std::pow(2.0 * a * xbar, 2), 1e-12 * mean);
    EXPECT_NEAR(full, 2.0 * lambda * a * a * second_moment(X, 0, 0), 1e-12 * full);
    EXPECT_GT(full, mean * (1.0 + 1e-3));
}

Material quadratic_material(double poisson) {
    Material m;
    m.young = 1e5;
    m.poisson = poisson;
    m.quadratic = true;
    return m;
}

TEST(QuadraticTet, LumpedMassesKeepTotalAndCentre) {
    World w = testing::world_from_mesh(generate_box(grid({0.03, 0.02, 0.01}, {3, 2, 2}, 0.2)), quadratic_material(0.3));
    ASSERT_EQ(w.quadratic.count(), w.elements.count());
    testing::expect_masses_keep_total_and_centre(w, 1000.0);
}

TEST(QuadraticTet, PatchTestHoldsOnAJitteredMesh) {
    const Vec3 size(0.03, 0.02, 0.01);
    World w = testing::world_from_mesh(generate_box(grid(size, {3, 2, 2}, 0.2)), quadratic_material(0.45));
    Eigen::Matrix3d A;
    A << 2e-3, -1e-3, 5e-4, 7e-4, -1.5e-3, 1e-3, -4e-4, 8e-4, 1.2e-3;
    testing::expect_patch_test(w, A, size, 3);
}

// The visual surface of a quadratic element follows its shape functions: under a displacement
// quadratic in x (a bent plate), every vertex of a twice-subdivided surface is exactly where the
// field puts it, where the corners' linear interpolation misses by up to a h^2 / 4 at an edge's
// midpoint; the collision surface stays on the corners' linear interpolation (its contacts' forces
// go to the corners by those weights).
TEST(QuadraticTet, TheVisualSurfaceShowsTheBendTheMidEdgeNodesCarry) {
    const Vec3 size(0.03, 0.02, 0.004);
    World w = testing::world_from_mesh(generate_box(grid(size, {3, 2, 1}, 0.2)), quadratic_material(0.3));
    const double a = 20.0;  // u_z = a x^2 [m]: 18 mm at x = 30 mm, 2 mm across a 10 mm cell
    auto bent = [&](const Vec3& X) { return Vec3(X.x(), X.y(), X.z() + a * X.x() * X.x()); };
    testing::place_bent_with_surfaces(w, bent, 2);
    ASSERT_GT(w.visual.vertex_count(), 100);
    double visual = 0.0, collision = 0.0;
    for (int v = 0; v < w.visual.vertex_count(); ++v) {
        const auto& n = w.elements.nodes[w.visual.element[v]];
        Vec3 rest = Vec3::Zero();
        for (int k = 0; k < 4; ++k) rest += w.visual.bary[v][k] * w.nodes.rest[n[k]];
        visual = std::max(visual, (w.visual.position[v] - bent(rest)).norm());
    }
    for (int v = 0; v < w.collision.vertex_count(); ++v) {
        const auto& n = w.elements.nodes[w.collision.element[v]];
        Vec3 rest = Vec3::Zero();
        for (int k = 0; k < 4; ++k) rest += w.collision.bary[v][k] * w.nodes.rest[n[k]];
        collision = std::max(collision, (w.collision.position[v] - bent(rest)).norm());
    }
    EXPECT_LT(visual, 1e-12 * a * size.x() * size.x()) << "the quadratic field, reproduced exactly";
    const double h = size.x() / 3;
    EXPECT_NEAR(collision, a * h * h / 4, 1e-9) << "the corners' linear interpolation at an edge's midpoint";
}

/// Mean downward tip deflection of a 0.2 x 0.01 x 0.01 m beam clamped at x = 0 under gravity [m].
double beam_deflection(bool quadratic, int n, double poisson, const std::string& method, int threads = 0,
                       bool mean_dilatation = false) {
    const int kept = configured_thread_count();
    if (threads > 0) set_thread_count(threads);
    Material m = quadratic_material(poisson);
    m.young = 2e8, m.quadratic = quadratic, m.mean_dilatation = mean_dilatation;
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    build_bodies(w, generate_box(grid({0.2, 0.01, 0.01}, {20 * n, n, n})));
    w.gravity = Vec3(0, 0, -9.81);
    SCOPED_TRACE(poisson);
    const double deflection = testing::clamped_tip_deflection(w, method, 0.2, 2);
    set_thread_count(kept);
    return deflection;
}

TEST(QuadraticTet, ABeamBendsAsBeamTheorySaysWhereTheLinearElementLocks) {
    // Timoshenko & Gere: q L^4 / (8 E I) + q L^2 / (2 kappa G A), nu = 0, q = rho g b h.
    const double q = 1000.0 * 9.81 * 1e-4, I = 1e-8 / 12.0, G = 1e8;
    const double exact = q * std::pow(0.2, 4) / (8.0 * 2e8 * I) + q * 0.04 / (2.0 * (5.0 / 6.0) * G * 1e-4);
    const double quadratic = beam_deflection(true, 1, 0.0, "cholesky"), linear = beam_deflection(false, 1, 0.0, "cholesky");
    std::printf("beam 20 x 1 x 1 cells: quadratic %+.2f %%, linear %+.2f %% from beam theory\n",
                100.0 * (quadratic / exact - 1.0), 100.0 * (linear / exact - 1.0));
    EXPECT_LT(std::abs(quadratic / exact - 1.0), 0.03);
    EXPECT_GT(std::abs(linear / exact - 1.0), 0.5);  // the locking the quadratic element removes
    // The matrix-free method reaches the same solution.
    EXPECT_NEAR(beam_deflection(true, 1, 0.0, "jacobi"), quadratic, 1e-6 * quadratic);
}

TEST(QuadraticTet, NearlyIncompressibleBeamConvergesWithoutLocking) {
    // nu 0.499: every assembled method's solve converges (beam_deflection checks it), and the beam
    // of 40 x 2 x 2 cells bends within 5 % of CalculiX's nu 0.49 deflection (1.146e-3 m; at 0.499
    // it is a little smaller still), where linear tetrahedra give a tenth of it.
    const double cholesky = beam_deflection(true, 2, 0.499, "cholesky"), amg = beam_deflection(true, 2, 0.499, "amg");
    const double linear = beam_deflection(false, 2, 0.499, "cholesky");
    std::printf("nu 0.499, 40 x 2 x 2 cells: quadratic %.5e m (amg %.5e m), linear %.5e m\n", cholesky, amg, linear);
    EXPECT_GT(cholesky, 0.95 * 1.146e-3);
    EXPECT_LT(cholesky, 1.146e-3);
    EXPECT_NEAR(amg, cholesky, 1e-6 * cholesky);
    EXPECT_LT(linear, 0.1 * cholesky);
}

// The constant pressure in a world: the assembled blocks (cholesky, amg) and the matrix-free
// products (jacobi) solve the nu 0.49 and 0.499 beams alike. Its volumetric energy is the square of
// the mean, never more than the mean of the squares (Jensen), so the beam is softer than with full
// integration: in bending too soft (+4 % of CalculiX's deflection, 1.146e-3 m, on these 40 x 2 x 2
// cells, where full integration is within 0.2 %: docs/elements.md says when to use which).
TEST(QuadraticTet, TheConstantPressureBeamSolvesAlikeWithEveryMethodAndIsSofter) {
    for (double nu : {0.49, 0.499}) {  // 20 x 1 x 1 cells
        const double cholesky = beam_deflection(true, 1, nu, "cholesky", 0, true);
        EXPECT_NEAR(beam_deflection(true, 1, nu, "jacobi", 0, true), cholesky, 1e-6 * cholesky) << nu;
        EXPECT_NEAR(beam_deflection(true, 1, nu, "amg", 0, true), cholesky, 1e-6 * cholesky) << nu;
    }
    const double reference = 1.146e-3;
    const double mean = beam_deflection(true, 2, 0.49, "cholesky", 0, true), full = beam_deflection(true, 2, 0.49, "cholesky");
    std::printf("nu 0.49, 40 x 2 x 2 cells: constant pressure %.5e m, full integration %.5e m\n", mean, full);
    EXPECT_GT(mean, full);
    EXPECT_LT(std::abs(mean / reference - 1.0), 0.05);
}

TEST(QuadraticTet, BitIdenticalOnOneAndTwoThreads) {
    const double one = beam_deflection(true, 1, 0.49, "jacobi", 1), two = beam_deflection(true, 1, 0.49, "jacobi", 2);
    EXPECT_EQ(one, two);
    const double c1 = beam_deflection(true, 1, 0.49, "cholesky", 1), c2 = beam_deflection(true, 1, 0.49, "cholesky", 2);
    EXPECT_EQ(c1, c2);
}

TEST(QuadraticTet, AutoKeepsCholeskyToFortyThousandDofs) {
    // 16.5k DOFs: past the linear element's 10k, within the quadratic one's 40k (the smoothed
    // aggregation serves the mid-edge nodes poorly: docs/elements.md).
    World w = testing::world_from_mesh(generate_box(grid({0.06, 0.04, 0.03}, {12, 8, 6})), quadratic_material(0.49));
    ASSERT_GT(3 * w.nodes.count(), 10000);
    ASSERT_LT(3 * w.nodes.count(), 40000);
    std::string why;
    EXPECT_EQ(resolve_linear_method(w, &why), "cholesky") << why;
    World big = testing::world_from_mesh(generate_box(grid({0.06, 0.04, 0.03}, {20, 14, 10})), quadratic_material(0.49));
    ASSERT_GT(3 * big.nodes.count(), 40000);
    EXPECT_EQ(resolve_linear_method(big, &why), "amg") << why;
}

TEST(QuadraticTet, RefusesALinearElementOnAQuadraticEdge) {
    const MeshData mesh = generate_box(grid({0.02, 0.01, 0.01}, {2, 1, 1}));
    World w;
    Material linear;
    linear.name = "fat";
    w.materials.list = {quadratic_material(0.3), linear};
    std::vector<uint16_t> material(mesh.cells.size(), 0);
    material.back() = 1;
    try {
        build_bodies(w, mesh, material);
        ADD_FAILURE() << "a mixed mesh was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("shares an edge with a quadratic one"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace xcut
