// Cutting 6-node triangles (2D) with XFEM (systems/cut/quadratic_enrichment.h, tri_side_rule): the
// shifted Heaviside over the 6 shape functions, phantoms at the mid-edge nodes, each side a quadratic
// entry with its side's rule and HRZ masses. Checked against closed forms, as the tetrahedron's:
// each piece of a plate cut through weighs rho t times its area and its mid-edge nodes take the side
// their rest point lies on; the piece cut off falls as implicit Euler moves a free body,
// x_n - X = g dt^2 n (n + 1) / 2, while the held one stays; a plate stretched along a cut through its
// whole length strains uniformly and stores E eps^2 V / 2.
#include <gtest/gtest.h>

#include "engine/io/generators.h"
#include "systems/cut/enrichment_system.h"
#include "systems/kernels/tet10_side_rule.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using namespace testing;

constexpr double kPlateL = 0.03, kPlateH = 0.01, kPlateT = 1e-3;  // plate: kPlateL x kPlateH, kPlateT thick [m]
constexpr double kPlateYoung = 1e5;                               // [Pa]

World quadratic_plate(double poisson, const Eigen::Vector3i& cells) {
    Material m;
    m.young = kPlateYoung, m.poisson = poisson, m.density = 1000.0, m.quadratic = true, m.thickness = kPlateT;
    World w = world_from_mesh(generate_plate(grid(Vec3(kPlateL, kPlateH, 0.0), cells, 0.2)), m);
    prepare_enrichment(w);
    return w;
}

/// Cuts the plate through along the line from (x0, -1) to (x1, 1) [m].
int cut_across(World& w, double x0, double x1) { return cut_now(w, {Vec3(x0, -1.0, 0.0), Vec3(x1, 1.0, 0.0)}); }

/// The side of the line from (x0, -1) to (x1, 1) rest point X lies on: +1 to its left (the side its
/// normal (-dy, dx) points to, as the cut's signs are taken).
int line_side(const Vec3& X, double x0, double x1) {
    const Vec3 n(-2.0, x1 - x0, 0.0);
    return n.dot(X - Vec3(x0, -1.0, 0.0)) > 0.0 ? 1 : -1;
}

/// The side a DOF node's material lies on: its mesh node's (a node the cut never met: its rest
/// point's), the other for a phantom.
int side_of_dof(const World& w, int d, double x0, double x1) {
    const int j = d < w.mesh_nodes ? d : w.enriched.node_of_phantom[d - w.mesh_nodes];
    const int own = w.enriched.sign[j] != 0 ? w.enriched.sign[j] : line_side(w.nodes.rest[j], x0, x1);
    return d < w.mesh_nodes ? own : -own;
}

// A side's rule and HRZ masses (tri_side_rule, tri6_side_masses): the whole triangle's masses are
// 1/19 at a corner and 16/57 at a mid-edge node, nothing in the slots a triangle does not use; a
// corner cut off at 0.4 and 0.3 of its two edges is 0.12 of the triangle, the rest 0.88, by the
// rule's weights and by the masses alike; the rule integrates x^2 over the corner as its closed form.
TEST(QuadraticTriCut, ASidesRuleAndMassesAreItsAreasAndTheTrianglesHrz) {
    const std::array<double, 10> whole = tri6_side_masses({1, 1, 1}, {0.0, 0.0, 0.0}, 1);
    for (int i = 0; i < 10; ++i) {
        const bool used = i < 3 || (i >= 4 && i <= 6);
        EXPECT_NEAR(whole[i], !used ? 0.0 : i < 3 ? kTri6CornerMass : kTri6EdgeMass, 1e-14) << i;
    }
    const std::array<double, 3> t{0.4, 0.0, 0.7};  // edge (0,1) at 0.4 from 0; edge (2,0) at 0.7 from 2
    for (int side : {1, -1}) {
        const double expected = side > 0 ? 0.4 * 0.3 : 1.0 - 0.4 * 0.3;
        const TetSideRule rule = tri_side_rule({1, -1, -1}, t, side);
        double weights = 0.0, masses = 0.0;
        for (int q = 0; q < rule.count; ++q) weights += rule.weight[q];
        for (double m : tri6_side_masses({1, -1, -1}, t, side)) masses += m;
        EXPECT_NEAR(weights, expected, 1e-14) << side;
        EXPECT_NEAR(masses, expected, 1e-14) << side;
    }
    // The corner triangle with vertices (0,0), (0.4,0), (0,0.3) in the reference triangle's (L_1, L_2):
    // the integral of L_1^2 over it is (area / 6) (0.4^2), over the parent's area 1/2: 0.12 * 0.16 / 6.
    const TetSideRule corner = tri_side_rule({1, -1, -1}, t, 1);
    double l1 = 0.0;
    for (int q = 0; q < corner.count; ++q) l1 += corner.weight[q] * corner.L[q][1] * corner.L[q][1];
    EXPECT_NEAR(l1, 0.12 * 0.16 / 6.0, 1e-15);
}

TEST(QuadraticTriCut, EachPieceWeighsRhoTimesItsAreaAndMidEdgeNodesTakeTheirPointsSide) {
    World w = quadratic_plate(0.3, {6, 2, 1});
    const double c = 0.0137;
    const int mesh_dofs = w.nodes.count();
    ASSERT_GT(cut_across(w, c, c), 0);
    EXPECT_GT(w.nodes.count(), mesh_dofs);
    double left = 0.0, right = 0.0;
    for (int d = 0; d < w.nodes.count(); ++d) (side_of_dof(w, d, c, c) > 0 ? left : right) += w.nodes.mass[d];
    const double rho_a = 1000.0 * kPlateH * kPlateT;
    EXPECT_NEAR(left, rho_a * c, 1e-12 * rho_a * kPlateL);
    EXPECT_NEAR(right, rho_a * (kPlateL - c), 1e-12 * rho_a * kPlateL);
    expect_mid_edge_nodes_take_their_points_side(w, [&](const Vec3& X) { return line_side(X, c, c); });
    for (double mass : w.nodes.mass) EXPECT_GT(mass, 0.0);
}

// The plate held at x = 0 under gravity (-y) and cut through obliquely: every DOF node of the piece
// cut off (phantoms and mid-edge nodes included) falls as implicit Euler moves a free body.
TEST(QuadraticTriCut, ThePieceCutOffFallsFreelyAndTheHeldOneStays) {
    World w = quadratic_plate(0.3, {6, 2, 1});
    hold_for_fall(w);
    w.gravity = Vec3(0.0, -9.81, 0.0);
    const double x0 = 0.0152, x1 = 0.0188;
    ASSERT_GT(cut_across(w, x0, x1), 0);
    // right of the line: the free end
    const FallCheck f = step_and_fall(w, 20, [&](int d) { return side_of_dof(w, d, x0, x1) < 0 ? 1 : 0; });
    EXPECT_GT(f.free_nodes, 20);
    EXPECT_LT(f.worst, 1e-6 * f.fall) << "fall " << f.fall;
    EXPECT_LT(f.held, 0.2 * f.fall);
}

// A plate clamped at both ends and stretched by delta, cut along its whole length by the line y = c
// (nu = 0): u = (delta x / L, 0) at every DOF node, strain energy E (delta / L)^2 V / 2; with the
// assembled Cholesky and the matrix-free Jacobi preconditioner.
TEST(QuadraticTriCut, AStretchAlongTheCutIsUniformAndStoresTheClosedFormEnergy) {
    expect_stretch_along_a_cut([] { return quadratic_plate(0.0, {4, 3, 1}); },
                               [](World& w) { return cut_now(w, {Vec3(-1.0, 0.0043, 0.0), Vec3(1.0, 0.0043, 0.0)}); },
                               kPlateL, kPlateYoung, kPlateL * kPlateH * kPlateT);
}

}  // namespace
}  // namespace xcut
