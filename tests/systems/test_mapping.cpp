// Visual surface bound to the alternative mesh (paper §3.2, Fig. 5): built closed and outward,
// every vertex bound to one live element after cuts, re-binding limited to the split elements,
// and vertices following their side's virtual element.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <numeric>
#include <set>

#include "systems/surface/mapping_system.h"
#include "tests/surface_checks.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::cut_now;
using testing::grid;
using testing::square_on_plane;
using testing::world_from_mesh;
using testing::check_closed_oriented;
using testing::components_of;
using testing::enclosed_volume;

class VisualSurface : public ::testing::TestWithParam<int> {};

TEST_P(VisualSurface, BoundaryIsClosedOutwardAndExact) {
    World w = world_from_mesh(generate_box(grid({0.03, 0.02, 0.01}, {3, 2, 2}, 0.2, 4)));
    build_visual_surface(w, GetParam());
    EXPECT_EQ(check_closed_oriented(w.visual), 2);
    EXPECT_NEAR(enclosed_volume(w.visual), 0.03 * 0.02 * 0.01, 1e-15) << "outward, and the box's volume";
    for (int v = 0; v < w.visual.vertex_count(); ++v) {
        EXPECT_NEAR(w.visual.bary[v].sum(), 1.0, 1e-15);
        EXPECT_GE(w.visual.bary[v].minCoeff(), 0.0);
    }
}

INSTANTIATE_TEST_SUITE_P(Subdivisions, VisualSurface, ::testing::Values(0, 1, 2));

TEST(Mapping, CutRebindsOnlyVerticesOfSplitElementsAndLosesNone) {
    World w = world_from_mesh(generate_box(grid({0.04, 0.02, 0.004}, {8, 4, 2})));
    build_visual_surface(w, 1);
    const int split = cut_now(w, square_on_plane(Vec3(0.021, 0.01, 0.002), Vec3(1, 0, 0), 1.0));
    ASSERT_GT(split, 0);
    size_t expected = 0;
    for (int c = 0; c < w.cuts.count(); ++c) expected += w.visual.bound_to[w.cuts.element[c]].size();
    EXPECT_GT(expected, 0u);
    EXPECT_EQ(rebind_cut_vertices(w), static_cast<int>(expected));
    EXPECT_EQ(rebind_cut_vertices(w), 0) << "nothing more to re-bind";
    testing::expect_bound_to_live_elements(w, w.visual);
    // Each re-bound vertex sits on its side of the cut plane x = 21 mm: the side of the nodes there.
    int right_sign = 0;
    for (int j = 0; j < w.mesh_nodes; ++j)
        if (w.enriched.enriched[j] && w.nodes.rest[j].x() > 0.021) right_sign = w.enriched.sign[j];
    ASSERT_NE(right_sign, 0);
    std::map<int, int> side_of_element;
    for (int k = 0; k < w.virtual_elements.count(); ++k)
        side_of_element[w.virtual_elements.element[k]] = w.virtual_elements.side[k];
    for (int c = 0; c < w.cuts.count(); ++c)
        for (int v : w.visual.bound_to[w.cuts.element[c]]) {
            const int ve = w.visual.element[v];
            Vec3 rest = Vec3::Zero();
            for (int a = 0; a < 4; ++a) rest += w.visual.bary[v][a] * w.nodes.rest[w.elements.nodes[ve][a]];
            if (std::abs(rest.x() - 0.021) < 1e-12) continue;  // a point of the cut itself: both sides have one
            EXPECT_EQ(side_of_element.at(ve), rest.x() > 0.021 ? right_sign : -right_sign) << "vertex " << v;
        }
}

TEST(Mapping, SurfaceOfTheFreePartFallsWithIt) {
    // The fully cut bar of problem 4: every surface vertex beyond the cut, including those bound to
    // virtual elements, falls with x_n = 1/2 g h^2 n (n + 1).
    Material m;
    m.young = 1e5;
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    build_bodies(w, generate_box(grid({0.1, 0.01, 0.01}, {10, 2, 2})));
    w.gravity = Vec3(0, 0, -9.81);
    w.solver.dt = 1e-3;
    w.solver.cg_tolerance = 1e-14;
    w.solver.cg_max_iterations = 2000;
    build_visual_surface(w, 1);
    cut_now(w, square_on_plane(Vec3(0.055, 0.005, 0.005), Vec3(1, 0, 0), 1.0));
    rebind_cut_vertices(w);
    std::vector<Vec3> rest = w.visual.position;
    for (int n = 1; n <= 20; ++n) {
        testing::step_world(w);
        update_surface_positions(w);
        const double expected = -0.5 * 9.81 * 1e-6 * n * (n + 1);
        for (int v = 0; v < w.visual.vertex_count(); ++v)
            if (rest[v].x() > 0.055 + 1e-6) {  // cut points sit up to 1e-6 of an edge off skin vertices
                ASSERT_NEAR(w.visual.position[v].z() - rest[v].z(), expected, 1e-9 * std::abs(expected)) << v;
            }
    }
}

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

class CutSurface : public ::testing::TestWithParam<int> {};

// A bar cut through: the surface becomes two closed, outward 2-manifolds (Euler characteristic 2
// each) whose volumes add up to the bar's, with no two vertices of one side at one place.
TEST_P(CutSurface, FullCutGivesTwoClosedSurfaces) {
    World w = world_from_mesh(generate_box(grid({0.1, 0.01, 0.01}, {10, 2, 2}, 0.0)));
    build_visual_surface(w, GetParam());
    ASSERT_GT(cut_now(w, square_on_plane(Vec3(0.0537, 0.005, 0.005), Vec3(1, 0.15, 0.1), 1.0)), 0);
    rebind_cut_vertices(w);
    update_surface_positions(w);
    SurfaceMesh& s = w.visual;
    EXPECT_GT(std::count(s.cut_face.begin(), s.cut_face.end(), 1), 0) << "the wound is closed by cut faces";
    int count = 0;
    const std::vector<int> comp = components_of(s, count);
    ASSERT_EQ(count, 2);
    double total = 0.0;
    for (int k = 0; k < 2; ++k) {
        const SurfaceMesh part = testing::component(s, comp, k);
        EXPECT_EQ(testing::euler_characteristic(part), 2) << "part " << k;
        const double v = enclosed_volume(part);
        EXPECT_GT(v, 0.0) << "outward";
        total += v;
    }
    EXPECT_NEAR(total, 0.1 * 0.01 * 0.01, 1e-12);
    testing::expect_no_duplicate_points(s);
}

INSTANTIATE_TEST_SUITE_P(Subdivisions, CutSurface, ::testing::Values(0, 1));

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

// 2D: the sheet itself is the visual mesh; a cut splits its triangles, each side keeping its part,
// so the incision shows as a gap: total area is kept and no triangle spans the cut.
TEST(Mapping, TwoDimensionalCutSplitsTheSheet) {
    World w = world_from_mesh(generate_plate(grid({0.04, 0.02, 0}, {8, 4, 1})));
    build_visual_surface(w, 1);
    ASSERT_GT(cut_now(w, {Vec3(0.021, -1, 0), Vec3(0.021, 1, 0)}), 0);
    rebind_cut_vertices(w);
    update_surface_positions(w);
    const SurfaceMesh& s = w.visual;
    double area = 0.0;
    for (const auto& t : s.triangles) {
        const Vec3 a = s.position[t[1]] - s.position[t[0]], b = s.position[t[2]] - s.position[t[0]];
        area += 0.5 * (a.x() * b.y() - a.y() * b.x());
        bool left = false, right = false;
        for (int k : t) {
            left = left || s.position[k].x() < 0.021 - 1e-12;
            right = right || s.position[k].x() > 0.021 + 1e-12;
        }
        EXPECT_FALSE(left && right) << "a triangle spans the cut";
    }
    EXPECT_NEAR(area, 0.04 * 0.02, 1e-15);
}

}  // namespace
}  // namespace xcut
