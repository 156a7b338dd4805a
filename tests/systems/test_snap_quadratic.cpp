// The snapping baseline on quadratic elements (systems/cut/snap_quadratic.h), checked against
// closed forms: a quadratic field is kept exactly at every node the cut moves or makes (a quadratic
// field is its own interpolant on every piece), every piece is a quadratic element whose mid-edge
// nodes lie at its edges' rest midpoints, a cut through frees two pieces that share no node (mid-edge
// ones included), the body's mass is kept, and the piece cut off falls as implicit Euler moves a
// free body, x_n - X = g dt^2 n (n + 1) / 2, while the held one stays.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/io/generators.h"
#include "engine/io/scene.h"
#include "systems/pipeline.h"
#include "systems/cut/cut_system.h"
#include "systems/cut/snap_cut_system.h"
#include "systems/kernels/disjoint_sets.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using namespace testing;

constexpr double kBarLength = 0.03, kBarSide = 0.01;  // bar: kBarLength x kBarSide x kBarSide [m]

World snap_bar(const Eigen::Vector3i& cells) {
    Material m;
    m.young = 1e5, m.poisson = 0.3, m.density = 1000.0, m.quadratic = true;
    World w = world_from_mesh(generate_box(grid(Vec3(kBarLength, kBarSide, kBarSide), cells, 0.2)), m);
    w.snap.enabled = true;
    prepare_snap_cut(w);
    return w;
}

/// A quadratic field over the bar: displacement (scale 1) or velocity [m, m/s].
Vec3 quadratic_field(const Vec3& X, double scale) {
    return scale * Vec3(50.0 * X.z() * X.z() + 3.0 * X.x() * X.y(), 20.0 * X.x() * X.x() - 4.0 * X.y() * X.z(),
                        30.0 * X.x() * X.y() + 0.01 * X.z());
}

/// Cuts the bar through by the plane n . X = n . p, the snapping cutter's way; returns the
/// elements split.
int cut_through(World& w, const Vec3& n, const Vec3& p) {
    queue_polygon_cut(w, square_on_plane(p, n, 0.1));
    return apply_snap_events(w);
}

/// The live elements joined through shared DOF nodes (their quadratic entries' 10): the component
/// of each DOF node a live element holds (-1: none).
std::vector<int> components(const World& w, int& count) {
    const std::vector<int> live = live_elements(w);
    DisjointSets sets(w.nodes.count());
    for (int e : live) {
        const auto& ids = w.quadratic.nodes[w.quadratic.of_element[e]];
        for (int j = 1; j < 10; ++j) sets.join(ids[0], ids[j]);
    }
    std::vector<int> of(w.nodes.count(), -1), root_id(w.nodes.count(), -1);
    count = 0;
    for (int e : live)
        for (int id : w.quadratic.nodes[w.quadratic.of_element[e]]) {
            const int r = sets.find(id);
            if (root_id[r] < 0) root_id[r] = count++;
            of[id] = root_id[r];
        }
    return of;
}

/// Moves every node by the quadratic field (in 2D its in-plane part) and its velocity by half of it,
/// cuts by `cut`, and checks what a cut through must keep: every node of every live piece (the
/// snapped ones, the edge points, their copies and the new mid-edge nodes) carries the field at its
/// rest point, every mid-edge node sits at its edge's rest midpoint, two pieces that share no node,
/// the mass.
template <class Cut>
void expect_the_cut_keeps_the_field(World& w, Cut&& cut) {
    const QuadraticElements& q = w.quadratic;
    const int npe = w.elements.nodes_per_element(), edges = q.planar ? 3 : 6;
    auto field = [&](const Vec3& X, double scale) {
        Vec3 u = quadratic_field(X, scale);
        if (q.planar) u.z() = 0.0;
        return u;
    };
    for (int i = 0; i < w.nodes.count(); ++i) {
        w.nodes.position[i] = w.nodes.rest[i] + field(w.nodes.rest[i], 1.0);
        w.nodes.velocity[i] = field(w.nodes.rest[i], 0.5);
    }
    double mass = 0.0;
    for (double m : w.nodes.mass) mass += m;
    ASSERT_GT(cut(w), 0);
    EXPECT_GT(w.snap.snaps, 0);
    EXPECT_GT(w.snap.points, 0);
    EXPECT_GT(w.snap.copies, 0);
    EXPECT_GT(w.snap.mid_nodes, 0);
    double worst_x = 0.0, worst_v = 0.0, worst_mid = 0.0;
    for (int e : live_elements(w)) {
        ASSERT_LT(e, static_cast<int>(q.of_element.size()));
        const int t = q.of_element[e];
        ASSERT_GE(t, 0) << "live element " << e << " has no quadratic entry";
        for (int a = 0; a < npe; ++a) EXPECT_EQ(q.nodes[t][a], w.elements.nodes[e][a]);
        for (int id : q.nodes[t]) {
            const Vec3& X = w.nodes.rest[id];
            worst_x = std::max(worst_x, (w.nodes.position[id] - X - field(X, 1.0)).norm());
            worst_v = std::max(worst_v, (w.nodes.velocity[id] - field(X, 0.5)).norm());
        }
        for (int k = 0; k < edges; ++k) {
            const Vec3 mid = 0.5 * (w.nodes.rest[q.nodes[t][kTet10Edges[k][0]]] + w.nodes.rest[q.nodes[t][kTet10Edges[k][1]]]);
            worst_mid = std::max(worst_mid, (w.nodes.rest[q.nodes[t][4 + k]] - mid).norm());
        }
    }
    EXPECT_LT(worst_x, 1e-13) << "the positions' largest displacement is about 5e-3 m";
    EXPECT_LT(worst_v, 1e-13);
    EXPECT_EQ(worst_mid, 0.0);
    int count = 0;
    components(w, count);
    EXPECT_EQ(count, 2) << "the cut goes through";
    double after = 0.0;
    for (double m : w.nodes.mass) after += m;
    EXPECT_NEAR(after, mass, 1e-12 * mass);
}

// An oblique cut through the bar, near nodes (so some snap) and across edges (so some get points).
TEST(SnapQuadratic, ACutKeepsAQuadraticFieldAtEveryNodeItMovesOrMakes) {
    World w = snap_bar({6, 2, 2});
    expect_the_cut_keeps_the_field(w, [](World& v) {
        return cut_through(v, Vec3(1.0, 0.2, -0.3).normalized(), Vec3(0.0137, kBarSide / 2, kBarSide / 2));
    });
}

// The same on 6-node triangles: a plate cut through by an oblique line.
TEST(SnapQuadratic, ACutKeepsTheFieldOnSixNodeTriangles) {
    Material m;
    m.young = 1e5, m.poisson = 0.3, m.density = 1000.0, m.quadratic = true;
    World w = world_from_mesh(generate_plate(grid(Vec3(kBarLength, kBarSide, 0.0), {6, 2, 1}, 0.2)), m);
    w.snap.enabled = true;
    prepare_snap_cut(w);
    ASSERT_TRUE(w.quadratic.planar);
    expect_the_cut_keeps_the_field(w, [](World& v) {
        queue_polygon_cut(v, {Vec3(0.0131, -1.0, 0.0), Vec3(0.0179, 1.0, 0.0)});
        return apply_snap_events(v);
    });
}

// The bar held at x = 0 under gravity and cut through by the snapping cutter: the piece cut off is
// free, so every DOF node of it falls as implicit Euler moves a free body; the held one sags far less.
TEST(SnapQuadratic, ThePieceCutOffFallsFreelyAndTheHeldOneStays) {
    World w = snap_bar({6, 2, 2});
    hold_for_fall(w);
    ASSERT_GT(cut_through(w, Vec3(1.0, 0.1, -0.15).normalized(), Vec3(0.0171, kBarSide / 2, kBarSide / 2)), 0);
    int count = 0;
    const std::vector<int> of = components(w, count);
    ASSERT_EQ(count, 2);
    const int held_piece = of[0];  // node 0 is at the origin, held
    const FallCheck f = step_and_fall(w, 20, [&](int d) { return of[d] < 0 ? -1 : of[d] == held_piece ? 0 : 1; });
    EXPECT_GT(f.free_nodes, 40);
    EXPECT_LT(f.worst, 1e-6 * f.fall) << "fall " << f.fall;
    EXPECT_LT(f.held, 0.2 * f.fall);
}

// A scene of quadratic tissue cut by a blade with the snapping cutter runs (the scene loader took
// it), cuts the cantilever through and lets its end fall, as the XFEM cutter does.
TEST(SnapQuadratic, ABladeCutsAQuadraticCantileverThroughWithEitherCutter) {
    double tip[2] = {0.0, 0.0};
    for (int k = 0; k < 2; ++k) {
        const std::string cutter = k == 0 ? "snap" : "xfem";
        SCOPED_TRACE(cutter);
        Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/cantilever.json",
                                 {"material.element=\"quadratic\"", "cutter.type=\"" + cutter + "\"", "duration=0.2",
                                  R"(tools+={"name": "scalpel", "blade": {"tip": [0, 0, -0.004], "heel": [0, 0, 0.014]}, )"
                                  R"("trajectory": [{"time": 0, "position": [0.0512, -0.004, 0]}, )"
                                  R"({"time": 0.1, "position": [0.0512, 0.014, 0]}]})"});
        auto sim = make_simulation(scene, /*with_output=*/false);
        for (int i = 0; i < 100; ++i) step_simulation(*sim);
        const World& w = sim->world;
        EXPECT_GT(k == 0 ? w.snap.elements_split : w.cuts.count(), 15);
        EXPECT_EQ(w.pieces.count, 2);
        double z = 0.0;
        int n = 0;
        for (int i = 0; i < w.mesh_nodes; ++i) {
            ASSERT_TRUE(w.nodes.position[i].allFinite());
            if (w.nodes.rest[i].x() > 0.0999) z += w.nodes.position[i].z() - w.nodes.rest[i].z(), ++n;
        }
        tip[k] = z / n;
    }
    // Cut at 0.05 s (the blade crosses the beam's width in 0.1 s), the end falls for the rest of the
    // run: far more than the clamped beam's static tip deflection (1.5e-4 m).
    EXPECT_LT(tip[0], -2e-3);
    EXPECT_LT(tip[1], -2e-3);
    EXPECT_NEAR(tip[0], tip[1], 0.01 * std::abs(tip[1])) << "both cutters free the same end (measured 0.02 % apart)";
}

}  // namespace
}  // namespace xcut
