// Crack-front (branch) enrichment in 3D: its quadrature against closed forms, its functions against
// the 2D tip's, its condensed term against its own force, and the enriched block against the exact
// plane-strain near-front field (Williams 1957), which is an exact 3D field along a straight front.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "systems/cut/crack_tip_system.h"
#include "systems/kernels/front_enrichment.h"
#include "systems/solver/solver_system.h"
#include "tests/systems/tip_term_check.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace crack_front_test {

using testing::cut_now;
using testing::grid;
using testing::world_from_mesh;

double rule_sum(const FrontRule& r, const std::function<double(const Vec3&)>& f) {
    double s = 0.0;
    for (const VolumePoint& p : r.points) s += p.weight * f(p.X);
    return s;
}

TEST(FrontEnrichment, TheRuleIntegratesOneOverRAlongAnEdgeAsTheClosedForm) {
    // The tetrahedron (0, e_x, e_y, e_z) with the front along its edge on z: its section at height z
    // is the right triangle of legs 1 - z at the front, where ∫ 1/r dA = (1 - z) √2 ln(1 + √2), so
    // ∫ 1/r dV = ln(1 + √2) / √2.
    const std::array<Vec3, 4> X = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    const FrontFrame f{Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ()};
    const FrontRule r = front_tet_rule(X, HalfSpace{}, f, 6, 6);
    const auto inverse_r = [&](const Vec3& p) { return 1.0 / front_distance(f, p); };
    EXPECT_NEAR(rule_sum(r, [](const Vec3&) { return 1.0; }), 1.0 / 6.0, 1e-15);
    // (The 6-point angular rule of 45-degree triangles: 2.4e-9 measured.)
    EXPECT_NEAR(rule_sum(r, inverse_r), std::log(1.0 + std::sqrt(2.0)) / std::sqrt(2.0), 1e-8);
    // The part with x >= 0.3 is the tetrahedron scaled by 0.7 from (1, 0, 0): its volume 0.7³ / 6.
    const FrontRule part = front_tet_rule(X, HalfSpace{Vec3(0.3, 0, 0), Vec3::UnitX()}, f, 6, 6);
    EXPECT_NEAR(rule_sum(part, [](const Vec3&) { return 1.0; }), std::pow(0.7, 3) / 6.0, 1e-15);
    // Its first moment: the centroid's x, (0.3 + 1 + 0.3 + 0.3) / 4 (the signed fans' points outside
    // the part cancel).
    EXPECT_NEAR(rule_sum(part, [](const Vec3& p) { return p.x(); }), 0.475 * std::pow(0.7, 3) / 6.0, 1e-15);
}

TEST(FrontEnrichment, ATetrahedronsRuleIsTheSumOfItsSidesRules) {
    // A tetrahedron the front crosses obliquely, split by a plane: the rules of its two sides add up
    // to its own, for the volume and for the singular 1/r, and the rule converges with its orders
    // (the suite's 6 x 6 against 12 x 16 points).
    const std::array<Vec3, 4> X = {Vec3(-0.4, -0.3, -0.5), Vec3(0.7, -0.2, 0.1), Vec3(0.1, 0.8, -0.2), Vec3(0.0, 0.1, 0.9)};
    const FrontFrame f{Vec3(0.05, 0.02, 0.0), Vec3(1, 0, 0.2).normalized(), Vec3(-0.2, 0.1, 1).normalized()};
    ASSERT_NEAR(f.direction.dot(f.tangent), 0.0, 1e-15);
    double from = 0, to = 0;
    ASSERT_TRUE(front_in_tet(X, f, from, to));
    const auto inverse_r = [&](const Vec3& p) { return 1.0 / front_distance(f, p); };
    const auto one = [](const Vec3&) { return 1.0; };
    const double volume = std::abs((X[1] - X[0]).dot((X[2] - X[0]).cross(X[3] - X[0]))) / 6.0;
    const HalfSpace up{Vec3(0.1, 0.1, 0.1), Vec3(0.3, -1, 0.4).normalized()}, down{up.point, -up.normal};
    const double whole = rule_sum(front_tet_rule(X, {}, f, 6, 6), inverse_r);
    const double fine = rule_sum(front_tet_rule(X, {}, f, 12, 16), inverse_r);
    EXPECT_NEAR(rule_sum(front_tet_rule(X, {}, f, 6, 6), one), volume, 1e-14);
    EXPECT_NEAR(rule_sum(front_tet_rule(X, up, f, 6, 6), one) + rule_sum(front_tet_rule(X, down, f, 6, 6), one), volume, 1e-14);
    EXPECT_NEAR(rule_sum(front_tet_rule(X, up, f, 6, 6), inverse_r) + rule_sum(front_tet_rule(X, down, f, 6, 6), inverse_r),
                whole, 5e-5 * whole);  // 1.7e-5 measured
    EXPECT_NEAR(whole, fine, 1e-5 * fine);  // 1.6e-6 measured
}

TEST(FrontEnrichment, ALowOrderRuleSignsItsFansWithThreePointsAtLeast) {
    // A blade's front takes 2 x 2 points per Duffy triangle (kBladeFrontRuleOrder); where the
    // front's point lies outside a section its fan's triangles are signed, and those take 3 x 3
    // (kSignedFanOrder): beside the tetrahedron, within a tenth of its size, every section is so,
    // and the rule is the 3 x 3 rule's bit for bit.
    const std::array<Vec3, 4> X = {Vec3(-0.4, -0.3, -0.5), Vec3(0.7, -0.2, 0.1), Vec3(0.1, 0.8, -0.2), Vec3(0.0, 0.1, 0.9)};
    const Vec3 tangent = Vec3(-0.2, 0.1, 1).normalized(), ahead = Vec3(1, 0, 0.2).normalized();
    FrontFrame beside{Vec3(0.05, 0.02, 0.0), ahead, tangent};
    double from = 0, to = 0;
    for (int k = 0; k < 200 && front_in_tet(X, beside, from, to); ++k) beside.point += 0.01 * ahead.cross(tangent);
    ASSERT_FALSE(front_in_tet(X, beside, from, to));
    const FrontRule low = front_tet_rule(X, {}, beside, 2, 3), three = front_tet_rule(X, {}, beside, 3, 3);
    ASSERT_GT(low.points.size(), 64u * 8u);  // the slab rule, not the conical one
    ASSERT_EQ(low.points.size(), three.points.size());
    for (size_t q = 0; q < low.points.size(); ++q) {
        EXPECT_EQ(low.points[q].weight, three.points[q].weight);
        EXPECT_EQ(low.points[q].X, three.points[q].X);
    }
    // Through it, the sections that hold the front's point take 2 x 2 (fewer points): each section's
    // area as exact as with 3 x 3 (the volume as the same slabs give it), and 1/r near the fine
    // rule's (5.6e-4 measured).
    const FrontFrame through{Vec3(0.05, 0.02, 0.0), ahead, tangent};
    ASSERT_TRUE(front_in_tet(X, through, from, to));
    const FrontRule crossed = front_tet_rule(X, {}, through, 2, 3, 3), crossed3 = front_tet_rule(X, {}, through, 3, 3, 3);
    EXPECT_LT(crossed.points.size(), crossed3.points.size());
    const auto one = [](const Vec3&) { return 1.0; };
    EXPECT_NEAR(rule_sum(crossed, one), rule_sum(crossed3, one), 1e-15);
    const auto inverse_r = [&](const Vec3& p) { return 1.0 / front_distance(through, p); };
    const double fine = rule_sum(front_tet_rule(X, {}, through, 12, 16), inverse_r);
    std::printf("1/r: %.3g of the fine rule's\n", std::abs(rule_sum(crossed, inverse_r) - fine) / fine);
    EXPECT_NEAR(rule_sum(crossed, inverse_r), fine, 2e-3 * fine);
}

TEST(FrontEnrichment, ATetrahedronOffTheCracksPlaneTakesTheConicalRule) {
    // Wholly on one side of the crack's plane: 64 points of the conical product rule, exact for the
    // volume and a quadratic, and within 2e-4 of the slab rule (forced by a half-space that keeps it
    // all) on the near-singular 1/r of a front one tenth of its size away (9.1e-5 measured).
    const std::array<Vec3, 4> X = {Vec3(0.1, 0.1, 0), Vec3(1.1, 0.1, 0.1), Vec3(0.2, 1.1, -0.1), Vec3(0.1, 0.2, 1)};
    const FrontFrame f{Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ()};  // the crack's plane: y = 0
    const FrontRule conical = front_tet_rule(X, HalfSpace{}, f, 6, 6);
    const FrontRule slabs = front_tet_rule(X, HalfSpace{Vec3(0, -1, 0), Vec3::UnitY()}, f, 6, 6);
    EXPECT_EQ(conical.points.size(), 64u);
    EXPECT_GT(slabs.points.size(), 10 * conical.points.size());
    const double volume = std::abs((X[1] - X[0]).dot((X[2] - X[0]).cross(X[3] - X[0]))) / 6.0;
    const auto y2 = [](const Vec3& p) { return p.y() * p.y(); };
    const auto inverse_r = [&](const Vec3& p) { return 1.0 / front_distance(f, p); };
    EXPECT_NEAR(rule_sum(conical, [](const Vec3&) { return 1.0; }), volume, 1e-15);
    EXPECT_NEAR(rule_sum(conical, y2), rule_sum(slabs, y2), 1e-13);
    EXPECT_NEAR(rule_sum(conical, inverse_r), rule_sum(slabs, inverse_r), 2e-4 * rule_sum(slabs, inverse_r));
    for (int side : conical.side) EXPECT_EQ(side, 1);
}

TEST(FrontEnrichment, APartFarFromTheFrontTakesTheConicalRuleOnEachSide) {
    // Behind the front (x < 0), two sizes from it, across the crack's plane y = 0 (one corner above
    // it): the conical rule on the tetrahedra of each side. Each side's volume is exact (the side
    // above is the tetrahedron similar at A, cut where its edges cross y = 0), as is its first
    // moment; clipped by z <= 0.5 (only D above), the whole less the tetrahedron cut off at D.
    const std::array<Vec3, 4> X = {Vec3(-3, 0.5, 0), Vec3(-2.5, -0.5, 0), Vec3(-3.5, -0.4, 0.2), Vec3(-3, -0.3, 1)};
    const FrontFrame f{Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ()};
    const FrontRule r = front_tet_rule(X, HalfSpace{}, f, 6, 6);
    EXPECT_EQ(r.points.size() % 64, 0u);  // 64 a tetrahedron: 1 above, 3 below (a prism)
    EXPECT_LE(r.points.size(), 4u * 64u);
    const double volume = std::abs((X[1] - X[0]).dot((X[2] - X[0]).cross(X[3] - X[0]))) / 6.0;
    double above = volume;
    std::array<Vec3, 4> small{X[0], X[0], X[0], X[0]};
    for (int b = 1; b < 4; ++b) {
        const double t = X[0].y() / (X[0].y() - X[b].y());
        above *= t, small[b] = X[0] + t * (X[b] - X[0]);
    }
    const Vec3 centre = (small[0] + small[1] + small[2] + small[3]) / 4.0;
    double up = 0.0, down = 0.0;
    Vec3 moment = Vec3::Zero();
    for (size_t q = 0; q < r.points.size(); ++q) {
        (r.side[q] > 0 ? up : down) += r.points[q].weight;
        if (r.side[q] > 0) moment += r.points[q].weight * r.points[q].X;
    }
    EXPECT_NEAR(up, above, 1e-14);
    EXPECT_NEAR(down, volume - above, 1e-14);
    EXPECT_LT((moment - above * centre).norm(), 1e-13);
    const FrontRule clipped = front_tet_rule(X, HalfSpace{Vec3(0, 0, 0.5), Vec3(0, 0, -1)}, f, 6, 6);
    EXPECT_NEAR(rule_sum(clipped, [](const Vec3&) { return 1.0; }), volume * (1.0 - 0.5 * 0.5 * 0.625), 1e-14);
    EXPECT_EQ(clipped.points.size() % 64, 0u);
}

TEST(FrontEnrichment, TheFunctionsAreTheTipsInTheFrontsPlane) {
    // At X = P + x1 d + x2 n + s t the functions are the 2D tip's at (x1, x2), whatever s; their
    // gradients have no part along the front and are the functions' derivatives.
    const FrontFrame f{Vec3(0.1, -0.2, 0.3), Vec3(0, 0.6, 0.8), Vec3(1, 0, 0)};
    const TipFrame plane{Vec2::Zero(), Vec2::UnitX()};
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 50; ++k) {
        const double x1 = u(rng), x2 = u(rng), s = u(rng);
        const Vec3 X = f.point + x1 * f.direction + x2 * f.normal() + s * f.tangent;
        const FrontValues F = front_functions(f, X, 0);
        const BranchValues B = branch_functions(plane, Vec2(x1, x2), 0);
        for (int l = 0; l < 4; ++l) {
            EXPECT_NEAR(F.f[l], B.f[l], 1e-14);
            EXPECT_NEAR(F.grad[l].dot(f.tangent), 0.0, 1e-13);
            for (int a = 0; a < 3; ++a) {
                const double h = 1e-7;
                const Vec3 e = Vec3::Unit(a) * h;
                const double fd = (front_functions(f, X + e, 0).f[l] - front_functions(f, X - e, 0).f[l]) / (2 * h);
                EXPECT_NEAR(F.grad[l][a], fd, 1e-6 * (1.0 + std::abs(fd))) << k << " " << l;
            }
        }
    }
}

constexpr double kSide = 0.02, kK = 0.01;  // block [m]; stress intensity [Pa sqrt(m)]

/// Mode I's near-front displacement in plane strain (Williams 1957; Anderson, Fracture Mechanics,
/// Table 2.2, kappa = 3 - 4 nu), front along z through `tip`, crack along -x [m]: an exact field of
/// 3D linear elasticity (no z dependence, no z displacement).
Vec3 plane_strain_mode_one(const Vec3& X, const Vec3& tip, const Material& m) {
    const Vec3 d = X - tip;
    const double r = std::hypot(d.x(), d.y()), theta = std::atan2(d.y(), d.x());
    const double mu = m.young / (2 * (1 + m.poisson)), kappa = 3 - 4 * m.poisson;
    const double a = kK / (2 * mu) * std::sqrt(r / (2 * std::numbers::pi)), s = std::sin(theta / 2), c = std::cos(theta / 2);
    return Vec3(a * c * (kappa - 1 + 2 * s * s), a * s * (kappa + 1 - 2 * c * c), 0.0);
}

Material block_material() {
    Material m;
    m.young = 1e4, m.poisson = 0.3;
    return m;
}

/// A block of n x (n + 1) x 2 cells (side kSide, 0.2 kSide thick along the front) cut from x = 0 to
/// the front at x = `tip_x`, y = kSide / 2, its boundary nodes held at the exact field, solved to
/// equilibrium with the front enriched within `radius` (< 0: not enriched). Returns the largest
/// nodal |u - u_exact| over the free nodes, over the largest |u_exact|.
double block_error(int n, double tip_x, double radius, int* functions = nullptr) {
    const Material m = block_material();
    const double thick = 0.2 * kSide;
    World w = world_from_mesh(generate_box(grid({kSide, kSide, thick}, {n, n + 1, 2})), m);
    const Vec3 tip(tip_x, 0.5 * kSide, 0.0);
    cut_now(w, {Vec3(-kSide, tip.y(), -thick), tip - Vec3(0, 0, thick), tip + Vec3(0, 0, 2 * thick),
                Vec3(-kSide, tip.y(), 2 * thick)});
    if (radius >= 0.0) enrich_crack_front(w, tip, Vec3(1, 0, 0), Vec3(0, 0, 1), TipZone{radius});
    if (functions) *functions = w.tips.functions();
    double scale = 0.0;
    for (int i = 0; i < w.mesh_nodes; ++i) {
        const Vec3& X = w.nodes.rest[i];
        scale = std::max(scale, plane_strain_mode_one(X, tip, m).norm());
        if (std::min({X.x(), X.y(), X.z(), kSide - X.x(), kSide - X.y(), thick - X.z()}) > 1e-12) continue;
        w.nodes.position[i] = w.nodes.rest[i] + plane_strain_mode_one(X, tip, m);
        w.nodes.fixed[i] |= 7;
    }
    const StaticResult r = static_solve(w, xcut_step_terms(), 1e-10, 10, 1e-13, 5000);
    EXPECT_TRUE(r.converged);
    double worst = 0.0;
    for (int i = 0; i < w.mesh_nodes; ++i) {
        if (w.nodes.fixed[i]) continue;
        const Vec3 u = w.nodes.position[i] - w.nodes.rest[i];
        worst = std::max(worst, (u - plane_strain_mode_one(w.nodes.rest[i], tip, m)).norm());
    }
    return worst / scale;
}

TEST(CrackFront, TheEnrichedBlockApproachesTheExactPlaneStrainField) {
    // The front on a cell's edge and inside a cell, 8 cells: the plain XFEM's nodal error is the
    // linear field's near the front; the front's functions take most of it away.
    for (double tip_x : {0.5 * kSide, 0.537 * kSide}) {
        int functions = 0;
        const double plain = block_error(8, tip_x, -1.0), local = block_error(8, tip_x, 0.0, &functions);
        const double zone = block_error(8, tip_x, 0.35 * kSide);
        std::printf("front at x = %.3f W: nodal error plain %.3g %%, front's elements %.3g %% (%d functions), "
                    "within 0.35 W %.3g %%\n", tip_x / kSide, 100 * plain, 100 * local, functions, 100 * zone);
        EXPECT_GT(plain, 3e-2);
        EXPECT_LT(local, 0.6 * plain);
        EXPECT_LT(zone, 0.3 * plain);
    }
}

TEST(CrackFront, ForceAndStiffnessAreConsistent) {
    // The condensed term's product is -df/dx in 3D, at a deformed state with the front inside elements.
    World w = world_from_mesh(generate_box(grid({kSide, kSide, 0.25 * kSide}, {5, 6, 2}, 0.15)), block_material());
    const Vec3 tip(0.55 * kSide, 0.5 * kSide, 0.0);
    cut_now(w, {Vec3(-kSide, tip.y(), -kSide), Vec3(tip.x(), tip.y(), -kSide), Vec3(tip.x(), tip.y(), kSide),
                Vec3(-kSide, tip.y(), kSide)});
    enrich_crack_front(w, tip, Vec3(1, 0, 0), Vec3(0, 0, 1), TipZone{0.3 * kSide});
    ASSERT_GT(w.tips.zone(), 0);
    const testing::TipTermCheck c = testing::check_tip_term(w, 5);
    EXPECT_LT(c.mismatch, 1e-6);
    EXPECT_GT(c.tip_share, 1e-3);
}

TEST(CrackFront, ARefusedFrontSaysWhy) {
    World box = world_from_mesh(generate_box(grid({kSide, kSide, kSide}, {2, 2, 2})));
    const Vec3 mid = Vec3::Constant(0.5 * kSide);
    EXPECT_THROW(enrich_crack_front(box, mid + Vec3(2 * kSide, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)), std::invalid_argument);
    EXPECT_THROW(enrich_crack_front(box, mid, Vec3(0, 0, 1), Vec3(0, 0, 1)), std::invalid_argument);
    EXPECT_THROW(enrich_crack_front(box, mid, Vec3(1, 0, 0), Vec3::Zero()), std::invalid_argument);
    EXPECT_THROW(enrich_crack_front(box, mid, Vec3(1, 0, 0), Vec3(0, 0, 1), TipZone{-1.0}), std::invalid_argument);
    World plate = world_from_mesh(generate_plate(grid({kSide, kSide, 0}, {2, 2, 1})));
    EXPECT_THROW(enrich_crack_front(plate, mid, Vec3(1, 0, 0), Vec3(0, 0, 1)), std::invalid_argument);
    EXPECT_NO_THROW(enrich_crack_front(box, mid, Vec3(1, 0, 0), Vec3(0, 0, 1)));
    EXPECT_GT(box.tips.zone(), 0);
}

}  // namespace crack_front_test
}  // namespace xcut
