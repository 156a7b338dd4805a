// Cut bodies (docs/verification.md problem 4, sign consistency, crack-front rule) in 3D and 2D.
#include <gtest/gtest.h>

#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::cut_now;
using testing::grid;
using testing::square_on_plane;
using testing::step_world;
using testing::world_from_mesh;

constexpr double kG = 9.81;     // [m/s^2]
constexpr double kCutX = 0.055; // cut plane x = 55 mm: the middle of an element, 10 mm cells

/// Bar 100 x 10 x 10 mm (3D) or 100 x 10 mm strip (2D), clamped at x = 0, gravity -z (-y in 2D).
World clamped_bar(int dim, double length = 0.1, int cells_x = 10) {
    Material m;
    m.young = 1e5;
    m.poisson = 0.3;
    m.density = 1000.0;
    m.thickness = 0.01;
    const MeshData mesh = dim == 3 ? generate_box(grid({length, 0.01, 0.01}, {cells_x, 2, 2}))
                                   : generate_plate(grid({length, 0.01, 0}, {cells_x, 2, 1}));
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    build_bodies(w, mesh);
    w.gravity = dim == 3 ? Vec3(0, 0, -kG) : Vec3(0, -kG, 0);
    w.solver.dt = 1e-3;
    w.solver.cg_tolerance = 1e-14;
    w.solver.cg_max_iterations = 2000;
    return w;
}

std::vector<Vec3> cut_across_bar(int dim) {
    if (dim == 2) return {Vec3(kCutX, -1, 0), Vec3(kCutX, 1, 0)};
    return square_on_plane(Vec3(kCutX, 0.005, 0.005), Vec3(1, 0, 0), 1.0);
}

/// DOF nodes carrying the free part: real nodes beyond the cut and phantoms of nodes before it.
std::vector<int> free_part(const World& w) {
    std::vector<int> out;
    for (int i = 0; i < w.nodes.count(); ++i) {
        const bool beyond = w.nodes.rest[i].x() > kCutX;
        if (i < w.mesh_nodes ? beyond : !beyond) out.push_back(i);
    }
    return out;
}

class FullyCutBar : public ::testing::TestWithParam<int> {};

// Problem 4: the free part falls with x_n = 1/2 g h^2 n(n+1) (implicit Euler, constant force).
TEST_P(FullyCutBar, FreePartFallsExactly) {
    const int dim = GetParam();
    World w = clamped_bar(dim);
    const int dofs_before = w.nodes.count();
    const int split = cut_now(w, cut_across_bar(dim));
    EXPECT_EQ(split, dim == 3 ? 2 * 2 * 6 : 2 * 2);  // one layer of cells, all its elements
    const int enriched = w.enriched.count();
    EXPECT_EQ(enriched, dim == 3 ? 2 * 3 * 3 : 2 * 3);  // both node layers of the cut cells
    EXPECT_EQ(w.nodes.count(), dofs_before + enriched);
    const std::vector<int> piece = free_part(w);
    const double h = w.solver.dt;
    const int axis = dim == 3 ? 2 : 1;
    for (int n = 1; n <= 40; ++n) {
        step_world(w);
        const double expected = -0.5 * kG * h * h * n * (n + 1);
        for (int i : piece)
            ASSERT_NEAR(w.nodes.position[i][axis] - w.nodes.rest[i][axis], expected, 1e-9 * std::abs(expected))
                << "step " << n << " node " << i;
    }
}

// Problem 4: each part's rigid motion gives zero elastic force (1e-10 relative).
TEST_P(FullyCutBar, RigidMotionOfEachPartIsForceFree) {
    const int dim = GetParam();
    World w = clamped_bar(dim);
    cut_now(w, cut_across_bar(dim));
    w.gravity.setZero();
    const std::vector<int> piece = free_part(w);
    const Mat3 Q = dim == 3 ? Mat3(Eigen::AngleAxisd(1.1, Vec3(0.2, 1, 0.4).normalized())) : Mat3(Eigen::AngleAxisd(1.1, Vec3::UnitZ()));
    for (int i : piece) w.nodes.position[i] = Q * w.nodes.rest[i] + Vec3(0.03, -0.02, dim == 3 ? 0.05 : 0.0);
    update_rotations(w);
    compute_forces(w);
    const double scale = w.materials.list[0].young * 0.01 * 0.01;  // E h^2 [N]
    EXPECT_LT(w.forces.force.cwiseAbs().maxCoeff(), 1e-10 * scale);
    EXPECT_LT(w.forces.elastic_energy, 1e-10 * scale * 0.01);
}

// Problem 4: the clamped part settles to a shorter bar's deflection: between the bars of length
// 50 and 60 mm on the same mesh (it ends at 55 mm, in the middle of a cell).
TEST_P(FullyCutBar, ClampedPartDeflectsLikeShorterBar) {
    const int dim = GetParam();
    const int axis = dim == 3 ? 2 : 1;
    auto deflection_at = [&](World& w, double x) {
        double sum = 0.0;
        int n = 0;
        for (int i = 0; i < w.mesh_nodes; ++i)
            if (std::abs(w.nodes.rest[i].x() - x) < 1e-9) sum += w.nodes.position[i][axis] - w.nodes.rest[i][axis], ++n;
        return sum / n;
    };
    World w = clamped_bar(dim);
    w.materials.list[0].young = 1e7;  // small deflection: the bars stay in the linear range
    cut_now(w, cut_across_bar(dim));
    for (int i : free_part(w)) w.nodes.fixed[i] = 7;  // the free part is gone for the static problem
    ASSERT_TRUE(static_solve(w, xcut_step_terms(), 1e-8, 30, 1e-12, 20000).converged);
    const double cut_bar = -deflection_at(w, 0.05);  // sag, positive down [m]
    World short_bar = clamped_bar(dim, 0.05, 5), long_bar = clamped_bar(dim, 0.06, 6), full = clamped_bar(dim);
    for (World* b : {&short_bar, &long_bar, &full}) b->materials.list[0].young = 1e7;
    ASSERT_TRUE(static_solve(short_bar, xcut_step_terms(), 1e-8, 30, 1e-12, 20000).converged);
    ASSERT_TRUE(static_solve(long_bar, xcut_step_terms(), 1e-8, 30, 1e-12, 20000).converged);
    ASSERT_TRUE(static_solve(full, xcut_step_terms(), 1e-8, 30, 1e-12, 20000).converged);
    const double lo = -deflection_at(short_bar, 0.05), hi = -deflection_at(long_bar, 0.05);
    EXPECT_GT(cut_bar, lo) << "sags more than the 50 mm bar";
    EXPECT_LT(cut_bar, hi) << "sags less than the 60 mm bar";
    EXPECT_GT(-deflection_at(full, 0.05), 2.0 * hi) << "the uncut bar sags far more: the cut did separate";
}

INSTANTIATE_TEST_SUITE_P(Dims, FullyCutBar, ::testing::Values(3, 2), [](const auto& info) {
    return info.param == 3 ? std::string("Tetrahedra") : std::string("Triangles");
});

// Every node of the cut region has one H for all its elements: each virtual element holds the
// real node exactly where H matches its side, and H agrees with the side of the cut plane.
TEST(XfemSigns, ConsistentAcrossElements) {
    World w = world_from_mesh(generate_box(grid({0.03, 0.02, 0.01}, {6, 4, 2}, 0.2, 17)));
    const Vec3 normal = Vec3(0.3, 1.0, 0.2).normalized(), centre(0.015, 0.0101, 0.005);
    ASSERT_GT(cut_now(w, square_on_plane(centre, normal, 1.0)), 10);
    for (int j = 0; j < w.mesh_nodes; ++j) {
        if (!w.enriched.enriched[j]) continue;
        const double level = (w.nodes.rest[j] - centre).dot(normal);
        EXPECT_EQ(w.enriched.sign[j], level >= 0 ? 1 : -1) << "node " << j;
    }
    for (int v = 0; v < w.virtual_elements.count(); ++v) {
        const int parent = w.virtual_elements.parent[v];
        const auto& verts = w.elements.nodes[w.virtual_elements.element[v]];
        for (int a = 0; a < 4; ++a) {
            const int j = w.elements.nodes[parent][a];
            const bool own_side = w.enriched.sign[j] == w.virtual_elements.side[v];
            EXPECT_EQ(verts[a] == j, own_side) << "virtual element " << v << " vertex " << a;
        }
    }
}

// Crack-front rule: a cut that stops inside the body does not open beyond its last cut element.
TEST(XfemCrackFront, PartialCutOpensOnlyWhereCut) {
    // Slab 40 x 20 x 4 mm, cut from the y = 0 edge up to y = 10 mm by the plane x = 21 mm, the
    // two ends pulled apart in x by held displacements.
    World w = world_from_mesh(generate_box(grid({0.04, 0.02, 0.004}, {8, 4, 2})));
    const double x_cut = 0.021;
    const std::vector<Vec3> poly = {Vec3(x_cut, -1, -1), Vec3(x_cut, 0.01, -1), Vec3(x_cut, 0.01, 1), Vec3(x_cut, -1, 1)};
    const int split = cut_now(w, poly);
    EXPECT_EQ(split, 2 * 2 * 6) << "two cells along y (10 mm of 5 mm cells), two through z";
    int held = 0, open = 0;
    for (int j = 0; j < w.mesh_nodes; ++j) {
        if (!w.enriched.enriched[j]) continue;
        if (w.enriched.front_fixed[j]) {
            ++held;
            EXPECT_NEAR(w.nodes.rest[j].y(), 0.01, 1e-12) << "only the front line y = 10 mm is held";
            EXPECT_LT(w.enriched.phantom[j], 0);
        } else {
            ++open;
        }
    }
    EXPECT_EQ(held, 2 * 3) << "both node columns x = 20, 25 mm at y = 10 mm, three z levels";
    EXPECT_GT(open, 0);
    for (int i = 0; i < w.nodes.count(); ++i) {
        const double x = w.nodes.rest[i].x();
        if (x < 1e-9 || x > 0.04 - 1e-9) {
            w.nodes.fixed[i] = 7;
            w.nodes.position[i].x() += x < 0.02 ? -1e-3 : 1e-3;
        }
    }
    ASSERT_TRUE(static_solve(w, xcut_step_terms(), 1e-8, 30, 1e-12, 20000).converged);
    double max_open = 0.0;
    for (int j = 0; j < w.mesh_nodes; ++j) {
        const double a = enriched_displacement(w, j).norm();
        if (w.enriched.front_fixed[j]) {
            EXPECT_EQ(a, 0.0);
        }
        max_open = std::max(max_open, a);
    }
    EXPECT_GT(max_open, 1e-4) << "the cut part opens under the pull";
    // Beyond the front (y > 10 mm) the material is continuous: no node there is enriched.
    for (int j = 0; j < w.mesh_nodes; ++j)
        if (w.nodes.rest[j].y() > 0.01 + 1e-9) {
            EXPECT_FALSE(w.enriched.enriched[j]);
        }
}

// Cutting the neighbour releases the front: extending the cut frees the held nodes.
TEST(XfemCrackFront, ExtendingTheCutReleasesTheFront) {
    World w = world_from_mesh(generate_box(grid({0.04, 0.02, 0.004}, {8, 4, 2})));
    const double x_cut = 0.021;
    cut_now(w, {Vec3(x_cut, -1, -1), Vec3(x_cut, 0.01, -1), Vec3(x_cut, 0.01, 1), Vec3(x_cut, -1, 1)});
    int held_before = 0;
    for (uint8_t f : w.enriched.front_fixed) held_before += f;
    ASSERT_GT(held_before, 0);
    cut_now(w, {Vec3(x_cut, -1, -1), Vec3(x_cut, 0.015, -1), Vec3(x_cut, 0.015, 1), Vec3(x_cut, -1, 1)});
    for (int j = 0; j < w.mesh_nodes; ++j) {
        if (std::abs(w.nodes.rest[j].y() - 0.01) < 1e-12 && w.enriched.enriched[j]) {
            EXPECT_FALSE(w.enriched.front_fixed[j]) << "node " << j << " on the old front is released";
            EXPECT_GE(w.enriched.phantom[j], 0);
        }
    }
    // Mass is conserved through both cuts.
    double mass = 0.0;
    for (double m : w.nodes.mass) mass += m;
    EXPECT_NEAR(mass, 1000.0 * 0.04 * 0.02 * 0.004, 1e-12);
}

}  // namespace
}  // namespace xcut
