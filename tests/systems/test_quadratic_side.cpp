// One side of a cut quadratic tetrahedron (systems/kernels/tet10_side_rule.h), against closed forms:
// the sides tile the element and weigh what the cut's volumes say; each side integrates quadratics
// exactly (a corner side is a tetrahedron of known moments; a plane x + y = c through the reference
// tetrahedron has polynomial moments); the sides' stiffnesses add up to the element's, each keeps
// the six rigid modes, and the energy of a quadratic field on a side is the closed-form integral.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "components/cut_elements.h"
#include "systems/kernels/cut_geometry.h"
#include "engine/io/generators.h"
#include "engine/quadratic_setup.h"
#include "systems/kernels/quadratic_elastic.h"
#include "systems/kernels/tet10_side_rule.h"
#include "systems/pipeline.h"
#include "systems/solver/solver_system.h"
#include "tests/test_helpers.h"
#include "tests/systems/quadratic_fixtures.h"

namespace xcut {
namespace {

using namespace testing;  // the quadratic fixtures

/// The crossings of the plane n . X = c with the element's edges (kTetEdges order), and its signs.
struct PlaneCut {
    std::array<int8_t, 4> H;
    std::array<double, 6> t{};
};
PlaneCut plane_cut(const std::array<Vec3, 4>& X, const Vec3& n, double c) {
    PlaneCut p;
    std::array<double, 4> phi;
    for (int a = 0; a < 4; ++a) phi[a] = n.dot(X[a]) - c, p.H[a] = phi[a] > 0.0 ? 1 : -1;
    for (int k = 0; k < 6; ++k) {
        const int a = kTetEdges[k][0], b = kTetEdges[k][1];
        if (p.H[a] != p.H[b]) p.t[k] = phi[a] / (phi[a] - phi[b]);
    }
    return p;
}

/// sum_q w_q V f(x_q) over the rule's points [f's unit m^3].
template <class F>
double integrate(const TetSideRule& rule, const std::array<Vec3, 4>& X, F f) {
    double s = 0.0;
    for (int q = 0; q < rule.count; ++q) {
        Vec3 x = Vec3::Zero();
        for (int i = 0; i < 4; ++i) x += rule.L[q][i] * X[i];
        s += rule.weight[q] * volume_of(X) * f(x);
    }
    return s;
}

TEST(QuadraticSide, SidesTileTheElementAndWeighWhatTheCutVolumesSay) {
    const auto X = corners();
    for (int pattern = 1; pattern < 15; ++pattern) {  // every way to put the nodes on two sides
        PlaneCut p;
        for (int a = 0; a < 4; ++a) p.H[a] = (pattern >> a) & 1 ? 1 : -1;
        for (int k = 0; k < 6; ++k) p.t[k] = 0.15 + 0.1 * k;
        double both = 0.0;
        for (int side : {1, -1}) {
            const TetSideRule rule = tet_side_rule(p.H, p.t, side);
            double sum = 0.0;
            for (int q = 0; q < rule.count; ++q) {
                EXPECT_GT(rule.weight[q], 0.0);
                EXPECT_NEAR(rule.L[q].sum(), 1.0, 1e-14);
                EXPECT_GT(rule.L[q].minCoeff(), 0.0);  // inside the element
                sum += rule.weight[q];
            }
            EXPECT_NEAR(sum, tet_side_volume(X, p.H, p.t, side) / volume_of(X), 1e-13) << pattern << " " << side;
            both += sum;
        }
        EXPECT_NEAR(both, 1.0, 1e-13) << pattern;
    }
}

TEST(QuadraticSide, ACornerSideAndItsPrismIntegrateQuadraticsExactly) {
    const auto X = corners();
    // A plane that leaves node 3 alone above it.
    const Vec3 n = Vec3(0.2, -0.3, 1.0).normalized();
    const double c = 0.6 * n.dot(X[3]) + 0.4 * n.dot(X[1]);
    const PlaneCut p = plane_cut(X, n, c);
    ASSERT_EQ(p.H[3], 1);
    ASSERT_EQ(p.H[0] + p.H[1] + p.H[2], -3);
    std::array<Vec3, 4> tip{X[3]};  // the corner side: node 3 and the three crossings toward it
    for (int k = 0, m = 1; k < 6; ++k)
        if (kTetEdges[k][1] == 3) tip[m++] = X[kTetEdges[k][0]] + p.t[k] * (X[3] - X[kTetEdges[k][0]]);
    const TetSideRule above = tet_side_rule(p.H, p.t, 1), below = tet_side_rule(p.H, p.t, -1);
    EXPECT_EQ(above.count, 4);
    EXPECT_EQ(below.count, 12);
    for (int a = 0; a < 3; ++a)
        for (int b = a; b < 3; ++b) {
            auto f = [&](const Vec3& x) { return x[a] * x[b]; };
            const double corner = std::abs(second_moment(tip, a, b)), whole = second_moment(X, a, b);
            EXPECT_NEAR(integrate(above, X, f), corner, 1e-13 * std::abs(whole)) << a << b;
            EXPECT_NEAR(integrate(below, X, f), whole - corner, 1e-13 * std::abs(whole)) << a << b;
        }
}

/// The reference tetrahedron scaled to h, and the plane x + y = c h (nodes 0 and 3 below it).
std::array<Vec3, 4> reference(double h) { return {Vec3::Zero(), Vec3(h, 0, 0), Vec3(0, h, 0), Vec3(0, 0, h)}; }

TEST(QuadraticSide, TwoPrismsIntegrateQuadraticsExactly) {
    const double h = 0.01, c = 0.37;
    const auto X = reference(h);
    const PlaneCut p = plane_cut(X, Vec3(1, 1, 0), c * h);
    const TetSideRule below = tet_side_rule(p.H, p.t, -1), above = tet_side_rule(p.H, p.t, 1);
    EXPECT_EQ(below.count, 12);
    EXPECT_EQ(above.count, 12);
    // Over {x + y < c h}, with u = (x + y) / h: the slice at u is a segment of length u h in x and
    // 1 - u in z: V = h^3 (c^2/2 - c^3/3), int x^2 = h^5 (c^4/12 - c^5/15),
    // int z^2 = h^5 (c^2/2 - c^3 + 3c^4/4 - c^5/5) / 3.
    const double V = std::pow(h, 3) * (c * c / 2 - c * c * c / 3);
    const double xx = std::pow(h, 5) * (std::pow(c, 4) / 12 - std::pow(c, 5) / 15);
    const double zz = std::pow(h, 5) * (c * c / 2 - std::pow(c, 3) + 0.75 * std::pow(c, 4) - std::pow(c, 5) / 5) / 3;
    const double tol = 1e-13 * std::pow(h, 5);
    EXPECT_NEAR(integrate(below, X, [](const Vec3&) { return 1.0; }), V, 1e-13 * std::pow(h, 3));
    EXPECT_NEAR(integrate(below, X, [](const Vec3& x) { return x.x() * x.x(); }), xx, tol);
    EXPECT_NEAR(integrate(below, X, [](const Vec3& x) { return x.z() * x.z(); }), zz, tol);
    EXPECT_NEAR(integrate(above, X, [](const Vec3& x) { return x.x() * x.x(); }), second_moment(X, 0, 0) - xx, tol);
}

TEST(QuadraticSide, TheSidesStiffnessesAddUpToTheElementsAndKeepItsRigidModes) {
    const auto X = corners();
    const Mat3 R = Eigen::AngleAxisd(0.4, Vec3(1, 0.3, -0.2).normalized()).toRotationMatrix();
    const Mat3 Dinv = dm_inverse(X);
    const double V = volume_of(X);
    const Eigen::MatrixXd whole = testing::tet10_matrix(tet10_gradients(Dinv), R, V, kLame);
    for (const Vec3& n : {Vec3(0.2, -0.3, 1.0), Vec3(1.0, 1.0, 0.1)}) {  // a corner alone; two and two
        const double c = n.normalized().dot(0.5 * (X[0] + X[3]) + Vec3(0.004, 0.003, 0.0));
        const PlaneCut p = plane_cut(X, n.normalized(), c);
        Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(30, 30);
        for (int side : {1, -1}) {
            const Tet10SideGradients G = tet10_side_gradients(Dinv, tet_side_rule(p.H, p.t, side));
            const Eigen::MatrixXd K = testing::tet10_matrix(G, R, V, kLame);
            sum += K;
            // Each side alone: symmetric, six rigid modes (rotated by R), no other zero mode.
            EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm());
            const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
            for (int k = 0; k < 6; ++k) EXPECT_LT(std::abs(ev[k]), 1e-10 * ev[29]) << side << " " << k;
            // Its product and diagonal are the matrix's.
            Tet10Vectors q, Kq, diagonal;
            Eigen::VectorXd qv(30);
            for (int j = 0; j < 10; ++j) q[j] = Vec3(std::cos(2.0 * j + 1), std::sin(j + 0.5), std::cos(11.0 * j)), qv.segment<3>(3 * j) = q[j];
            tet10_stiffness_product(q, G, R, V, kLame, Kq);
            tet10_stiffness_diagonal(G, R, V, kLame, diagonal);
            const Eigen::VectorXd Kqv = K * qv;
            for (int j = 0; j < 10; ++j) {
                EXPECT_LT((Kqv.segment<3>(3 * j) - Kq[j]).norm(), 1e-12 * K.norm() * qv.norm()) << j;
                for (int a = 0; a < 3; ++a) EXPECT_NEAR(diagonal[j][a], K(3 * j + a, 3 * j + a), 1e-12 * K.norm());
            }
        }
        EXPECT_LT((sum - whole).norm(), 1e-12 * whole.norm());
    }
}

TEST(QuadraticSide, ASidesEnergyOfAQuadraticFieldIsTheClosedFormIntegralAnyWayItTurns) {
    const double h = 0.01, c = 0.37, k = 2.0;  // u = (k x^2, 0, 0): eps_xx = 2 k x [k in 1/m]
    const auto X = reference(h);
    const PlaneCut p = plane_cut(X, Vec3(1, 1, 0), c * h);
    const Tet10SideGradients G = tet10_side_gradients(dm_inverse(X), tet_side_rule(p.H, p.t, -1));
    const Tet10Vectors rest = nodes_of(X);
    const double xx = std::pow(h, 5) * (std::pow(c, 4) / 12 - std::pow(c, 5) / 15);
    const double exact = (0.5 * kLame.lambda + kLame.mu) * 4.0 * k * k * xx;  // energy density (lambda/2 + mu) eps_xx^2
    const Mat3 Q = Eigen::AngleAxisd(0.9, Vec3(-0.3, 1, 0.6).normalized()).toRotationMatrix();
    for (const Mat3& turn : {Mat3(Mat3::Identity()), Q}) {
        Tet10Vectors x, f;
        for (int j = 0; j < 10; ++j) x[j] = turn * (rest[j] + Vec3(k * rest[j].x() * rest[j].x(), 0, 0)) + Vec3(0.1, 0, -0.2);
        const double e = tet10_forces(x, G, turn, volume_of(X), kLame, f);
        EXPECT_NEAR(e, exact, 1e-12 * exact);
        Vec3 total = Vec3::Zero();  // the side's forces balance
        for (const Vec3& fj : f) total += fj;
        EXPECT_LT(total.norm(), 1e-12 * f[1].norm());
    }
}

TEST(QuadraticSide, SideMassesAreHrzOfTheSidesConsistentMass) {
    // Uncut: the whole element's HRZ shares.
    const std::array<double, 6> none{};
    const std::array<double, 10> whole = tet10_side_masses({1, 1, 1, 1}, none, 1);
    for (int i = 0; i < 10; ++i) EXPECT_NEAR(whole[i], i < 4 ? kTet10CornerMass : kTet10EdgeMass, 1e-14) << i;
    // A plane x + y + z = m h leaves node 0 alone. On the reference tetrahedron, with
    // int x^k = k! / (k + 3)! (times m^(k + 3) over the corner x + y + z < m):
    //   int_corner N_1^2 = m^3 (4 m^4 4!/7! - 4 m^3 3!/6! + m^2 2!/5!), N_1 = x (2x - 1);
    //   int_corner N_0^2 = int_0^m (1 - u)^2 (1 - 2u)^2 u^2 / 2 du, N_0 = L_0 (2 L_0 - 1), L_0 = 1 - u;
    //   over the whole element both are 1/420.
    const double m = 0.6;
    const PlaneCut p = plane_cut(reference(0.01), Vec3(1, 1, 1), m * 0.01);
    ASSERT_EQ(p.H[0], -1);
    const double n1 = std::pow(m, 3) * (4 * std::pow(m, 4) * 24.0 / 5040 - 4 * std::pow(m, 3) * 6.0 / 720 + m * m * 2.0 / 120);
    auto primitive = [](double u) {  // of (1 - u)^2 (1 - 2u)^2 u^2 / 2 = (u^2 - 6u^3 + 13u^4 - 12u^5 + 4u^6) / 2
        return (std::pow(u, 3) / 3 - 1.5 * std::pow(u, 4) + 2.6 * std::pow(u, 5) - 2 * std::pow(u, 6) + 4 * std::pow(u, 7) / 7) / 2;
    };
    const double n0 = primitive(m) - primitive(0.0);
    const std::array<double, 10> corner = tet10_side_masses(p.H, p.t, -1), rest = tet10_side_masses(p.H, p.t, 1);
    EXPECT_NEAR(corner[0] / corner[1], n0 / n1, 1e-12 * n0 / n1);
    EXPECT_NEAR(rest[0] / rest[1], (1.0 / 420 - n0) / (1.0 / 420 - n1), 1e-12);
    double sum_corner = 0.0, sum_rest = 0.0;
    for (int i = 0; i < 10; ++i) {
        EXPECT_GT(rest[i], 0.0) << i;
        EXPECT_GE(corner[i], 0.0) << i;
        sum_corner += corner[i], sum_rest += rest[i];
    }
    EXPECT_NEAR(sum_corner, m * m * m, 1e-14);  // the sides' volume fractions: the masses' totals
    EXPECT_NEAR(sum_rest, 1.0 - m * m * m, 1e-14);
}

// An element given as its two sides (two entries over the same nodes, each with its side's rule)
// acts as the whole element: the same energy, nodal forces, stiffness product and diagonal.
TEST(QuadraticSide, AnElementGivenAsItsTwoSidesActsAsTheWhole) {
    Material m;
    m.young = 1e5, m.poisson = 0.45, m.quadratic = true;
    World w = world_from_mesh(generate_box(grid(Vec3(0.03, 0.02, 0.01), {3, 2, 1}, 0.2)), m);
    ASSERT_GT(w.quadratic.count(), 10);
    for (int i = 0; i < w.nodes.count(); ++i)
        w.nodes.position[i] = w.nodes.rest[i] + 1e-3 * Vec3(std::sin(7.0 * i), std::cos(3.0 * i), std::sin(5.0 * i + 1));
    std::vector<Vec3> p(w.nodes.count());
    for (int i = 0; i < w.nodes.count(); ++i) p[i] = Vec3(std::cos(2.0 * i), std::sin(i + 0.3), std::cos(9.0 * i));
    struct Sums {
        double energy = 0.0;
        std::vector<Vec3> force, product, diagonal;
    };
    auto sums = [&]() {
        const QuadraticView v{w.quadratic, w.elements, w.materials};
        std::vector<Tet10Vectors> buffer;
        Sums s;
        s.energy = quadratic_forces(v, w.nodes.position.data(), buffer);
        for (int i = 0; i < w.nodes.count(); ++i) s.force.push_back(quadratic_gathered(w.quadratic, buffer, i));
        quadratic_products(v, p.data(), buffer);
        for (int i = 0; i < w.nodes.count(); ++i) s.product.push_back(quadratic_gathered(w.quadratic, buffer, i));
        quadratic_diagonals(v, buffer);
        for (int i = 0; i < w.nodes.count(); ++i) s.diagonal.push_back(quadratic_gathered(w.quadratic, buffer, i));
        return s;
    };
    const Sums whole = sums();
    // Element 5 cut by a plane through its interior: the entry keeps side +1, a new one takes -1.
    QuadraticElements& q = w.quadratic;
    const int t0 = 5, e = q.element[t0];
    std::array<Vec3, 4> X;
    for (int a = 0; a < 4; ++a) X[a] = w.nodes.rest[w.elements.nodes[e][a]];
    const Vec3 n = Vec3(0.3, 1.0, -0.4).normalized();
    const PlaneCut cut = plane_cut(X, n, n.dot(0.25 * (X[0] + X[1] + X[2] + X[3])));
    q.side_rule.assign(q.count(), -1);
    q.side_rules = {tet_side_rule(cut.H, cut.t, 1), tet_side_rule(cut.H, cut.t, -1)};
    ASSERT_GT(q.side_rules[0].count, 0);
    ASSERT_GT(q.side_rules[1].count, 0);
    q.side_rule[t0] = 0;
    q.element.push_back(e), q.nodes.push_back(q.nodes[t0]), q.side_rule.push_back(1);
    build_quadratic_incidence(w);
    const Sums sides = sums();
    EXPECT_NEAR(sides.energy, whole.energy, 1e-12 * whole.energy);
    double fmax = 0.0, pmax = 0.0, dmax = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i)
        fmax = std::max(fmax, whole.force[i].norm()), pmax = std::max(pmax, whole.product[i].norm()),
        dmax = std::max(dmax, whole.diagonal[i].norm());
    for (int i = 0; i < w.nodes.count(); ++i) {
        EXPECT_LT((sides.force[i] - whole.force[i]).norm(), 1e-12 * fmax) << i;
        EXPECT_LT((sides.product[i] - whole.product[i]).norm(), 1e-12 * pmax) << i;
        EXPECT_LT((sides.diagonal[i] - whole.diagonal[i]).norm(), 1e-12 * dmax) << i;
    }
}

// The same through the assembled solver: a block whose boundary nodes are held on an affine field
// x = Q (I + G) X, with two of its elements given as their two sides, brings its inner nodes (started
// at rest) onto that field, as the whole elements do (the patch test), with the assembled
// Cholesky-preconditioned CG and the matrix-free Jacobi one. A side turns with its own material
// (quadratic_rotation), which for an affine field is the whole element's turn, so a wrong side block
// weight or rotation shows.
TEST(QuadraticSide, ElementsGivenAsTheirSidesSolveAsTheWhole) {
    Material m;
    m.young = 1e5, m.poisson = 0.45, m.quadratic = true;
    const Vec3 size(0.03, 0.01, 0.01);
    Mat3 G;
    G << 0.02, 0.01, -0.005, 0.004, -0.01, 0.008, 0.003, 0.006, 0.015;
    const Mat3 A = Eigen::AngleAxisd(0.4, Vec3(1.0, -2.0, 0.5).normalized()).toRotationMatrix() * (Mat3::Identity() + G);
    auto solved = [&](bool split, const std::string& method) {
        World w = world_from_mesh(generate_box(grid(size, {3, 2, 2}, 0.2)), m);
        std::vector<bool> inner(w.nodes.count(), false);
        for (int i = 0; i < w.nodes.count(); ++i) {
            const Vec3 X = w.nodes.rest[i];
            inner[i] = (X.array() > 1e-12).all() && (X.array() < size.array() - 1e-12).all();
            if (inner[i]) continue;
            w.constraints.nodes.push_back(i);
            w.nodes.position[i] = A * X;
        }
        EXPECT_GT(std::count(inner.begin(), inner.end(), true), 10);
        apply_constraints(w);
        QuadraticElements& q = w.quadratic;
        std::vector<int> split_ones;  // two elements with three or more inner nodes
        for (int t = 0; t < q.count() && split_ones.size() < 2; ++t)
            if (std::count_if(q.nodes[t].begin(), q.nodes[t].end(), [&](int j) { return inner[j]; }) >= 3) split_ones.push_back(t);
        EXPECT_EQ(split_ones.size(), 2u);
        if (split) {
            q.side_rule.assign(q.count(), -1);
            for (int t0 : split_ones) {
                const int e = q.element[t0];
                std::array<Vec3, 4> X;
                for (int a = 0; a < 4; ++a) X[a] = w.nodes.rest[w.elements.nodes[e][a]];
                const Vec3 n = Vec3(1.0, 0.2, 0.1).normalized();
                const PlaneCut cut = plane_cut(X, n, n.dot(0.25 * (X[0] + X[1] + X[2] + X[3])));
                q.side_rule[t0] = static_cast<int>(q.side_rules.size());
                q.side_rules.push_back(tet_side_rule(cut.H, cut.t, 1));
                q.side_rules.push_back(tet_side_rule(cut.H, cut.t, -1));
                q.element.push_back(e), q.nodes.push_back(q.nodes[t0]), q.side_rule.push_back(q.side_rule[t0] + 1);
            }
            build_quadratic_incidence(w);
        }
        w.solver.linear = method;
        const StaticResult r = static_solve(w, xcut_step_terms(), 1e-11, 60, 1e-13, 5000);
        EXPECT_TRUE(r.converged) << method << " " << split << ": " << r.residual << " after " << r.newton_iterations;
        double worst = 0.0;
        for (int i = 0; i < w.nodes.count(); ++i) worst = std::max(worst, (w.nodes.position[i] - A * w.nodes.rest[i]).norm());
        return worst;
    };
    EXPECT_LT(solved(false, "cholesky"), 1e-9);
    for (const std::string method : {"cholesky", "jacobi"}) EXPECT_LT(solved(true, method), 1e-9) << method;  // [m]
}

}  // namespace
}  // namespace xcut
