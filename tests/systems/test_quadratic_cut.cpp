// Cutting quadratic tetrahedra (docs/elements.md, "Cutting quadratic elements", step 2): the
// shifted Heaviside over the 10 shape functions, phantoms at the mid-edge nodes, and each side a
// quadratic entry with its side's rule and HRZ masses (systems/cut/quadratic_enrichment.h). Checked
// against closed forms: each piece of a bar cut through weighs rho times its volume and its
// mid-edge nodes take the side their rest point lies on; the piece cut off falls as implicit Euler
// moves a free body (x_n = g dt^2 n (n + 1) / 2) while the held one stays; a bar stretched along a
// cut through all its length strains uniformly and stores E eps^2 V / 2.
#include <gtest/gtest.h>

#include "engine/io/generators.h"
#include "systems/cut/cut_system.h"
#include "systems/cut/enrichment_system.h"
#include "systems/tool_system.h"
#include "systems/pipeline.h"
#include "systems/solver/solver_system.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using namespace testing;

constexpr double kL = 0.03, kH = 0.01;  // bar: kL x kH x kH [m]

constexpr double kYoung = 1e5;  // [Pa]

World quadratic_bar(double poisson, const Eigen::Vector3i& cells) {
    Material m;
    m.young = kYoung, m.poisson = poisson, m.density = 1000.0, m.quadratic = true;
    World w = world_from_mesh(generate_box(grid(Vec3(kL, kH, kH), cells, 0.2)), m);
    prepare_enrichment(w);
    return w;
}

/// The mesh node a DOF node stands for, and the side of the cut its material lies on (a node the
/// cut never met: the side of its rest point).
int side_of_dof(const World& w, int d, const Vec3& n, double c) {
    const int j = d < w.mesh_nodes ? d : w.enriched.node_of_phantom[d - w.mesh_nodes];
    const int own = w.enriched.sign[j] != 0 ? w.enriched.sign[j] : (n.dot(w.nodes.rest[j]) > c ? 1 : -1);
    return d < w.mesh_nodes ? own : -own;
}

/// Cuts the bar through by the plane n . X = c.
int cut_bar(World& w, const Vec3& n, double c) { return cut_now(w, square_on_plane(c * n + Vec3(kL, kH, kH) / 2 - n * n.dot(Vec3(kL, kH, kH) / 2), n, 0.1)); }

/// The bar held at x = 0 under gravity, solved tightly (CG to 1e-12), for the fall tests.
World held_bar() {
    World w = quadratic_bar(0.3, {6, 2, 2});
    hold_for_fall(w);
    return w;
}
const Vec3 kFallNormal = Vec3(1.0, 0.1, -0.15).normalized();  // the oblique cut of the fall tests
const Vec3 kFallPoint(0.0171, kH / 2, kH / 2);                 // a point on it [m]
constexpr int kFallSteps = 20;

/// Steps the cut bar kFallSteps times; returns the free fall x_n - X = g dt^2 n (n + 1) / 2 [m]
/// and the largest distance of a DOF node on the side n . X > c from it (`worst`).
double fall_and_worst(World& w, const Vec3& n, double c, double& worst) {
    for (int s = 0; s < kFallSteps; ++s) step_world(w);
    const double fall = 9.81 * w.solver.dt * w.solver.dt * kFallSteps * (kFallSteps + 1) / 2.0;
    worst = 0.0;
    for (int d = 0; d < w.nodes.count(); ++d)
        if (side_of_dof(w, d, n, c) > 0)
            worst = std::max(worst, (w.nodes.position[d] - w.nodes.rest[d] - Vec3(0.0, 0.0, -fall)).norm());
    return fall;
}

// A bar cut through at x = c: each piece's DOF nodes carry rho times its volume, every mid-edge
// node the cut met lies on the side its rest point is on, and the mid-edge nodes of split edges
// have a phantom.
TEST(QuadraticCut, EachPieceWeighsRhoTimesItsVolumeAndMidEdgeNodesTakeTheirPointsSide) {
    World w = quadratic_bar(0.3, {6, 2, 2});
    const Vec3 n = Vec3::UnitX();
    const double c = 0.0137;
    const int mesh_dofs = w.nodes.count();
    ASSERT_GT(cut_bar(w, n, c), 0);
    EXPECT_GT(w.nodes.count(), mesh_dofs);
    double left = 0.0, right = 0.0;
    for (int d = 0; d < w.nodes.count(); ++d) (side_of_dof(w, d, n, c) < 0 ? left : right) += w.nodes.mass[d];
    const double rho_a = 1000.0 * kH * kH;
    EXPECT_NEAR(left, rho_a * c, 1e-12 * rho_a * kL);
    EXPECT_NEAR(right, rho_a * (kL - c), 1e-12 * rho_a * kL);
    expect_mid_edge_nodes_take_their_points_side(w, [&](const Vec3& X) { return X.x() > c ? 1 : -1; });
    for (double mass : w.nodes.mass) EXPECT_GT(mass, 0.0);
}

// The bar held at x = 0 and cut through at x = c under gravity: the piece cut off is free, so
// every DOF node of it (phantoms and mid-edge nodes included) falls as implicit Euler moves a free
// body, x_n - X = g dt^2 n (n + 1) / 2; the held piece sags far less.
TEST(QuadraticCut, ThePieceCutOffFallsFreelyAndTheHeldOneStays) {
    World w = held_bar();
    const Vec3 n = kFallNormal;
    const double c = n.dot(kFallPoint);
    ASSERT_GT(cut_bar(w, n, c), 0);
    double worst = 0.0, held = 0.0;
    const double fall = fall_and_worst(w, n, c, worst);
    int free_dofs = 0;
    for (int d = 0; d < w.nodes.count(); ++d) {
        if (side_of_dof(w, d, n, c) > 0)
            ++free_dofs;
        else
            held = std::max(held, (w.nodes.position[d] - w.nodes.rest[d]).norm());
    }
    EXPECT_GT(free_dofs, 20);
    EXPECT_LT(worst, 1e-6 * fall) << "fall " << fall;
    // The held piece, a cantilever of about c, sags at most twice its static rho g A c^4 / (8 E I).
    const double sag = 1000.0 * 9.81 * kH * kH * std::pow(kFallPoint.x(), 4) / (8.0 * kYoung * std::pow(kH, 4) / 12.0);
    EXPECT_LT(held, 2.5 * sag) << "sag " << sag;
    EXPECT_LT(2.5 * sag, 0.2 * fall);
}

// The same cut made on the progressive front in two stages: first as far as y = kH / 2 (the elements
// it enters split as tip elements, their other split edges held), then through. Once the blade has
// crossed every edge, no node, corner or mid-edge, is held: the piece falls freely as above.
TEST(QuadraticCut, APieceCutOffInTwoStagesOnTheProgressiveFrontFallsFreely) {
    World w = held_bar();
    const Vec3 n = kFallNormal;
    const double c = n.dot(kFallPoint);
    const Vec3 centre = c * n + Vec3(kL, kH, kH) / 2 - n * n.dot(Vec3(kL, kH, kH) / 2);
    // A band of the plane from y = -1 to y = kH / 2 (the plane is nearly x = c: its y extent is y's).
    const Vec3 u = (Vec3::UnitY() - n * n.y()).normalized(), v = n.cross(u);
    const double low = u.dot(Vec3(0.0, -1.0, 0.0) - centre), high = u.dot(Vec3(0.0, kH / 2, 0.0) - centre);
    queue_polygon_cut(w, {centre + low * u - v, centre + high * u - v, centre + high * u + v, centre + low * u + v}, true);
    ASSERT_GT(apply_cut_events(w), 0);
    int held = 0;
    for (int c0 = 0; c0 < w.cuts.count(); ++c0) held += w.cuts.crossed[c0] != 0xFF;
    ASSERT_GT(held, 0) << "the first stage leaves tip elements";
    for (int c0 = 0; c0 < w.cuts.count(); ++c0) {  // the blade crosses the rest of every tip element
        CutEvent ev;
        ev.element = w.cuts.element[c0];
        w.pending_cuts.push_back(ev);
    }
    queue_polygon_cut(w, square_on_plane(centre, n, 0.1));
    apply_cut_events(w);
    double worst = 0.0;
    const double fall = fall_and_worst(w, n, c, worst);
    EXPECT_LT(worst, 1e-6 * fall) << "fall " << fall;
}

// A bar clamped at both ends and stretched by delta, cut along its whole length by the plane
// y = c (nu = 0): each piece strains uniformly, u = (delta x / L, 0, 0) at every DOF node, and the
// strain energy is E (delta / L)^2 V / 2; with the assembled Cholesky and the matrix-free Jacobi
// preconditioner.
TEST(QuadraticCut, AStretchAlongTheCutIsUniformAndStoresTheClosedFormEnergy) {
    expect_stretch_along_a_cut([] { return quadratic_bar(0.0, {4, 3, 2}); },
                               [](World& w) { return cut_bar(w, Vec3::UnitY(), 0.0043); }, kL, kYoung, kL * kH * kH);
}

/// The bar bent by the field u(X) = (50 z^2, 0, 20 x^2) [m] (5 mm and 18 mm at the far edges), which
/// its quadratic elements hold exactly; returns u.
Vec3 bend(World& w) {
    auto u = [](const Vec3& X) { return Vec3(50.0 * X.z() * X.z(), 0.0, 20.0 * X.x() * X.x()); };
    for (int d = 0; d < w.nodes.count(); ++d) w.nodes.position[d] = w.nodes.rest[d] + u(w.nodes.rest[d]);
    return u(Vec3(kL, 0.0, kH));
}

/// The largest distance from the plane n . x = c of the bent bar's cut points, each placed at
/// X + u(X) from its rest point X [m]; `points` counts them.
double cut_points_off_plane(const World& w, const Vec3& n, double c, int& points) {
    double worst = 0.0;
    points = 0;
    for (int k = 0; k < w.cuts.count(); ++k)
        for (int p = 0; p < 4; ++p) {
            if (w.cuts.point_edge[k][p] < 0) continue;
            const Vec3 X = w.cuts.points[k][p];
            worst = std::max(worst, std::abs(n.dot(X + Vec3(50.0 * X.z() * X.z(), 0.0, 20.0 * X.x() * X.x())) - c));
            ++points;
        }
    return worst;
}

// A bent quadratic element's edges are curves: a cut crosses each where the curve meets the cut's
// plane, its parameter the rest edge's. Checked against the closed form: every cut point, placed by
// the bending field at its rest point, lies on the plane to rounding, for a scripted plane and for
// a blade swept along it (through the corners' chords the points are off by up to 3e-4 m).
TEST(QuadraticCut, ACutCrossesABentElementsCurvedEdgesWhereTheyMeetThePlane) {
    {
        World w = quadratic_bar(0.3, {6, 2, 2});
        bend(w);
        const Vec3 n = Vec3(1.0, 0.3, 0.0).normalized(), o(0.0151, kH / 2, 0.01);
        ASSERT_GT(cut_now(w, square_on_plane(o, n, 0.1)), 10);
        int points = 0;
        EXPECT_LT(cut_points_off_plane(w, n, n.dot(o), points), 1e-12);
        EXPECT_GT(points, 40);
    }
    World w = quadratic_bar(0.3, {6, 2, 2});
    bend(w);
    const double c = 0.0151;  // the blade sweeps the plane x = c, across y, spanning z
    std::vector<Keyframe> path(2);
    path[0].position = Vec3(c, -0.005, 0.0), path[1].position = Vec3(c, kH + 0.005, 0.0), path[1].time = 1.0;
    add_scalpel(w, "scalpel", path, Vec3(0.0, 0.0, -0.01), Vec3(0.0, 0.0, 0.05));
    ElementBvh bvh;
    for (double t = 0.0; t < 1.0 + 1e-12; t += 0.05) {
        advance_tools(w, t);
        run_cut_system(w, bvh);
        apply_cut_events(w);
    }
    int points = 0;
    EXPECT_LT(cut_points_off_plane(w, Vec3::UnitX(), c, points), 1e-12);
    EXPECT_GT(w.cuts.count(), 10);
    EXPECT_GT(points, 40);
}

}  // namespace
}  // namespace xcut
