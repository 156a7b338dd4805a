// The 6-node triangle (2D, plane stress; systems/kernels/quadratic_tet.h, tri3_gradients): its
// integrals against closed forms, its rigid-motion invariance and rank, the agreement of its force,
// product, blocks and diagonal; in a world: its HRZ masses, the linear patch test, a clamped beam
// against beam theory where the 3-node triangle locks, determinism, a scene that runs and is cut.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "engine/io/generators.h"
#include "engine/io/scene.h"
#include "engine/parallel.h"
#include "engine/setup.h"
#include "systems/kernels/quadratic_tet.h"
#include "systems/kernels/tet10_side_rule.h"
#include "systems/pipeline.h"
#include "systems/solver/solver_system.h"
#include "systems/surface/mapping_system.h"
#include "tests/systems/quadratic_fixtures.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::grid;

/// A triangle of no symmetry in the xy plane [m], its Dm^-1 (2D, embedded as the mesh stores it)
/// and area.
const std::array<Vec3, 3> kTriangle{Vec3(0.01, 0.02, 0.0), Vec3(0.13, 0.03, 0.0), Vec3(0.04, 0.11, 0.0)};

Mat3 dm_inverse_2d() {
    Eigen::Matrix2d D;
    for (int k = 0; k < 2; ++k) D.col(k) = (kTriangle[k + 1] - kTriangle[0]).head<2>();
    Mat3 out = Mat3::Identity();
    out.topLeftCorner<2, 2>() = D.inverse();
    return out;
}

double area() {
    const Vec3 u = kTriangle[1] - kTriangle[0], v = kTriangle[2] - kTriangle[0];
    return 0.5 * (u.x() * v.y() - u.y() * v.x());
}

/// The element's 10 node slots: corners, the phantom corner (node 0), the edges' midpoints, and the
/// phantom edges (node 4), as QuadraticElements keeps a triangle.
Tet10Vectors nodes_of_triangle() {
    Tet10Vectors out;
    for (int a = 0; a < 3; ++a) out[a] = kTriangle[a];
    out[3] = kTriangle[0];
    for (int k = 0; k < 3; ++k) out[4 + k] = 0.5 * (kTriangle[kTet10Edges[k][0]] + kTriangle[kTet10Edges[k][1]]);
    out[7] = out[8] = out[9] = out[4];
    return out;
}

/// Closed form of the integral of x_a x_b over the triangle: A/12 (sum_i x_ia x_ib + sum x_ia sum x_ib).
double triangle_moment(int a, int b) {
    double ab = 0.0, sa = 0.0, sb = 0.0;
    for (const Vec3& p : kTriangle) ab += p[a] * p[b], sa += p[a], sb += p[b];
    return area() / 12.0 * (ab + sa * sb);
}

Tet10SideGradients triangle_gradients() { return tet10_side_gradients(dm_inverse_2d(), tri6_rule(), true); }

/// Plane-stress Lamé parameters [Pa] (lambda = 2 lambda_3D mu / (lambda_3D + 2 mu)).
const LameParameters kPlaneStress{2.0e4, 1.2e4};

TEST(QuadraticTri, IntegratesTheEnergyOfQuadraticFieldsExactly) {
    const Tet10Vectors rest = nodes_of_triangle();
    const Tet10SideGradients G = triangle_gradients();
    const double k = 1e-2, V = area();  // thickness 1 m
    Tet10Vectors x, f;
    // u = (k x^2, 0): eps_xx = 2 k x, energy density (lambda/2 + mu) 4 k^2 x^2.
    for (int j = 0; j < 10; ++j) x[j] = rest[j] + Vec3(k * rest[j].x() * rest[j].x(), 0, 0);
    const double e1 = tet10_forces(x, G, Mat3::Identity(), V, kPlaneStress, f);
    const double exact1 = (0.5 * kPlaneStress.lambda + kPlaneStress.mu) * 4.0 * k * k * triangle_moment(0, 0);
    EXPECT_NEAR(e1, exact1, 1e-12 * exact1);
    // u = (0, k x y): eps_yy = k x, eps_xy = k y / 2: density mu k^2 (x^2 + y^2 / 2) + lambda k^2 x^2 / 2.
    for (int j = 0; j < 10; ++j) x[j] = rest[j] + Vec3(0, k * rest[j].x() * rest[j].y(), 0);
    const double e2 = tet10_forces(x, G, Mat3::Identity(), V, kPlaneStress, f);
    const double exact2 = kPlaneStress.mu * k * k * (triangle_moment(0, 0) + 0.5 * triangle_moment(1, 1)) +
                          0.5 * kPlaneStress.lambda * k * k * triangle_moment(0, 0);
    EXPECT_NEAR(e2, exact2, 1e-12 * exact2);
}

TEST(QuadraticTri, RigidMotionGivesNoForceAndNoEnergy) {
    const Tet10Vectors rest = nodes_of_triangle();
    const Mat3 Q = Eigen::AngleAxisd(0.7, Vec3::UnitZ()).toRotationMatrix();
    Tet10Vectors x, f;
    for (int j = 0; j < 10; ++j) x[j] = Q * rest[j] + Vec3(0.3, -0.1, 0.0);
    EXPECT_NEAR(tet10_forces(x, triangle_gradients(), Q, area(), kPlaneStress, f), 0.0, 1e-18);
    for (const Vec3& fj : f) EXPECT_LT(fj.norm(), 1e-10);
}

// At a frozen R the force is linear in x with -K as its slope; K from the blocks is the product's,
// symmetric, its diagonal the diagonal kernel's, and on the 12 in-plane DOFs of the 6 nodes it has
// exactly the 3 rigid modes of the plane as zero-energy modes (the 3-point rule integrates it fully);
// the phantom slots get no force and no stiffness.
TEST(QuadraticTri, ForceProductBlocksAndDiagonalAgree) {
    const Tet10SideGradients G = triangle_gradients();
    const Tet10Vectors rest = nodes_of_triangle();
    const Mat3 R = Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix();
    Tet10Vectors x, p, f0, f1, Kp;
    for (int j = 0; j < 10; ++j) {
        x[j] = R * rest[j] + 1e-3 * Vec3(std::sin(3.0 * j), std::cos(5.0 * j), 0.0);
        p[j] = Vec3(std::cos(2.0 * j + 1), std::sin(j + 0.5), 0.0);
    }
    for (int j : {3, 7, 8, 9}) x[j] = x[j == 3 ? 0 : 4], p[j] = p[j == 3 ? 0 : 4];
    tet10_forces(x, G, R, area(), kPlaneStress, f0);
    Tet10Vectors xp = x;
    for (int j = 0; j < 10; ++j) xp[j] += p[j];
    tet10_forces(xp, G, R, area(), kPlaneStress, f1);
    tet10_stiffness_product(p, G, R, area(), kPlaneStress, Kp);
    double scale = 0.0;
    for (int j = 0; j < 10; ++j) scale = std::max(scale, Kp[j].norm());
    for (int j = 0; j < 10; ++j) EXPECT_LT((f1[j] - f0[j] + Kp[j]).norm(), 1e-10 * scale) << j;
    for (int j : {3, 7, 8, 9}) EXPECT_EQ(f0[j].norm() + Kp[j].norm(), 0.0) << j;
    const Eigen::MatrixXd K = testing::tet10_matrix(G, R, area(), kPlaneStress);
    EXPECT_LT((K - K.transpose()).norm(), 1e-10 * K.norm());
    Tet10Vectors diagonal;
    tet10_stiffness_diagonal(G, R, area(), kPlaneStress, diagonal);
    Eigen::MatrixXd plane(12, 12);
    for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 6; ++b)
            plane.block<2, 2>(2 * a, 2 * b) = K.block<2, 2>(3 * kTri6Locals[a], 3 * kTri6Locals[b]);
    for (int a = 0; a < 6; ++a)
        for (int c = 0; c < 2; ++c) EXPECT_NEAR(diagonal[kTri6Locals[a]][c], plane(2 * a + c, 2 * a + c), 1e-10 * K.norm());
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(plane).eigenvalues();
    for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(ev[k]), 1e-10 * ev[11]) << k;
    EXPECT_GT(ev[3], 1e-6 * ev[11]);
}

Material triangle_material(double poisson) {
    Material m;
    m.young = 1e5, m.poisson = poisson, m.quadratic = true, m.thickness = 2e-3;
    return m;
}

TEST(QuadraticTri, LumpedMassesKeepTotalAndCentre) {
    World w = testing::world_from_mesh(generate_plate(grid({0.03, 0.02, 0}, {3, 2, 1}, 0.2)), triangle_material(0.3));
    ASSERT_TRUE(w.quadratic.planar);
    ASSERT_EQ(w.quadratic.count(), w.elements.count());
    double volume = 0.0;
    for (int e = 0; e < w.elements.count(); ++e) volume += w.elements.rest_volume[e];
    EXPECT_NEAR(volume, 0.03 * 0.02 * 2e-3, 1e-15);
    testing::expect_masses_keep_total_and_centre(w, 1000.0);
}

TEST(QuadraticTri, PatchTestHoldsOnAJitteredMesh) {
    const Vec3 size(0.03, 0.02, 0.0);
    World w = testing::world_from_mesh(generate_plate(grid(size, {3, 2, 1}, 0.2)), triangle_material(0.45));
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    A.topLeftCorner<2, 2>() << 2e-3, -1e-3, 7e-4, -1.5e-3;
    testing::expect_patch_test(w, A, size, 2);
}

// The visual surface of 6-node triangles follows their shape functions: under u_y = a x^2 every
// vertex of a twice-subdivided sheet is where the field puts it (the corners' linear interpolation
// misses by a h^2 / 4 at an edge's midpoint).
TEST(QuadraticTri, TheVisualSurfaceShowsTheBendTheMidEdgeNodesCarry) {
    World w = testing::world_from_mesh(generate_plate(grid({0.03, 0.02, 0.0}, {3, 2, 1}, 0.2)), triangle_material(0.3));
    const double a = 20.0;  // [1/m]
    auto bent = [&](const Vec3& X) { return Vec3(X.x(), X.y() + a * X.x() * X.x(), 0.0); };
    testing::place_bent_with_surfaces(w, bent, 2);
    ASSERT_GT(w.visual.vertex_count(), 50);
    double worst = 0.0, linear = 0.0;
    for (int v = 0; v < w.visual.vertex_count(); ++v) {
        const auto& n = w.elements.nodes[w.visual.element[v]];
        Vec3 rest = Vec3::Zero(), chord = Vec3::Zero();
        for (int k = 0; k < 3; ++k) rest += w.visual.bary[v][k] * w.nodes.rest[n[k]], chord += w.visual.bary[v][k] * w.nodes.position[n[k]];
        worst = std::max(worst, (w.visual.position[v] - bent(rest)).norm());
        linear = std::max(linear, (chord - bent(rest)).norm());
    }
    EXPECT_LT(worst, 1e-12 * a * 0.03 * 0.03);
    EXPECT_GT(linear, 1e-4) << "the corners alone would not show the bend";
}

/// Mean downward tip deflection of a 0.2 x 0.01 m plane-stress beam (1 mm thick) clamped at x = 0
/// under gravity (-y), 20n x n cells [m].
double plate_beam_deflection(bool quadratic, int n, const std::string& method, int threads = 0) {
    const int kept = configured_thread_count();
    if (threads > 0) set_thread_count(threads);
    Material m = triangle_material(0.0);
    m.young = 2e8, m.quadratic = quadratic, m.thickness = 1e-3;
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    build_bodies(w, generate_plate(grid({0.2, 0.01, 0.0}, {20 * n, n, 1})));
    w.gravity = Vec3(0, -9.81, 0);
    const double deflection = testing::clamped_tip_deflection(w, method, 0.2, 1);
    set_thread_count(kept);
    return deflection;
}

TEST(QuadraticTri, ABeamBendsAsBeamTheorySaysWhereTheLinearTriangleLocks) {
    // Timoshenko & Gere: q L^4 / (8 E I) + q L^2 / (2 kappa G A), nu = 0, q = rho g t h.
    const double t = 1e-3, h = 0.01, q = 1000.0 * 9.81 * t * h, I = t * h * h * h / 12.0, G = 1e8;
    const double exact = q * std::pow(0.2, 4) / (8.0 * 2e8 * I) + q * 0.04 / (2.0 * (5.0 / 6.0) * G * t * h);
    const double quadratic = plate_beam_deflection(true, 1, "cholesky"), linear = plate_beam_deflection(false, 1, "cholesky");
    std::printf("plane-stress beam 20 x 1 cells: 6-node %+.2f %%, 3-node %+.2f %% from beam theory\n",
                100.0 * (quadratic / exact - 1.0), 100.0 * (linear / exact - 1.0));
    EXPECT_LT(std::abs(quadratic / exact - 1.0), 0.03);
    EXPECT_GT(std::abs(linear / exact - 1.0), 0.5);
    EXPECT_NEAR(plate_beam_deflection(true, 1, "jacobi"), quadratic, 1e-6 * quadratic);
}

TEST(QuadraticTri, BitIdenticalOnOneAndTwoThreads) {
    EXPECT_EQ(plate_beam_deflection(true, 1, "jacobi", 1), plate_beam_deflection(true, 1, "jacobi", 2));
    EXPECT_EQ(plate_beam_deflection(true, 1, "cholesky", 1), plate_beam_deflection(true, 1, "cholesky", 2));
}

// A 2D scene of 6-node triangles runs (a plate sagging under gravity); the face skin's scalpel cuts
// one through as it cuts the 3-node triangles (the same elements split, every step finite), with
// either cutter.
TEST(QuadraticTri, ASceneRunsAndABladeCutsIt) {
    const std::string plate = R"({ "mesh": { "generator": "plate", "size": [0.03, 0.02, 0], "cells": [6, 4, 1] },
        "material": { "element": "quadratic" }, "constraints": { "fixed_boxes": [ { "min": [-1, -1, -1], "max": [1e-9, 1, 1] } ] },
        "gravity": [0, -9.81, 0], "duration": 0.05 })";
    auto sim = make_simulation(load_scene_text(plate, "plate", "."), /*with_output=*/false);
    ASSERT_TRUE(sim->world.quadratic.planar);
    for (int i = 0; i < 25; ++i) step_simulation(*sim);
    double sag = 0.0;
    for (int i = 0; i < sim->world.nodes.count(); ++i) {
        ASSERT_TRUE(sim->world.nodes.position[i].allFinite());
        sag = std::max(sag, sim->world.nodes.rest[i].y() - sim->world.nodes.position[i].y());
    }
    EXPECT_GT(sag, 1e-6);
    // XFEM on 6-node and 3-node triangles, then the snapping cutter on 6-node ones.
    int split[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        std::vector<std::string> set = {k != 1 ? "material.element=\"quadratic\"" : "material.element=\"linear\""};
        if (k == 2) set.push_back("cutter.type=\"snap\"");
        auto face = make_simulation(load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/face_skin_2d.json", set), false);
        EXPECT_EQ(face->world.quadratic.planar, k != 1);
        for (int i = 0; i < 120; ++i) step_simulation(*face);
        for (const Vec3& x : face->world.nodes.position) ASSERT_TRUE(x.allFinite());
        split[k] = k == 2 ? face->world.snap.elements_split : face->world.cuts.count();
    }
    EXPECT_GT(split[0], 15);
    EXPECT_EQ(split[0], split[1]);
    EXPECT_GT(split[2], 15);
}

}  // namespace
}  // namespace xcut
