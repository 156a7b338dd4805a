// The semi-progressive cutter (paper §3.3, Fig. 14): which elements a scalpel splits.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "engine/io/scene_checks.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "systems/cut/cut_system.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/tool_system.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::grid;
using testing::world_from_mesh;

constexpr double kX = 0.031;  // incision plane x [m], in the middle of a 2 mm cell

/// Slab 40 x 20 x 2 mm with 2 mm cells and a vertical scalpel edge through its thickness.
World slab_with_scalpel(const std::vector<Keyframe>& path, double threshold = 0.0) {
    World w = world_from_mesh(generate_box(grid({0.04, 0.02, 0.002}, {20, 10, 1})));
    add_scalpel(w, "scalpel", path, Vec3(0, 0, -0.001), Vec3(0, 0, 0.003));
    w.cut_state.threshold = threshold;
    return w;
}

Keyframe key(double t, double x, double y) {
    Keyframe k;
    k.time = t;
    k.position = Vec3(x, y, 0.0);
    return k;
}

/// Steps the cutter alone (no dynamics: the body stays at rest) along the trajectory.
std::set<int> run_cutter(World& w, double t_end, double dt) {
    ElementBvh bvh;
    std::set<int> split;
    for (double t = 0.0; t < t_end + 1e-12; t += dt) {
        advance_tools(w, t);
        run_cut_system(w, bvh);
        for (const CutEvent& ev : w.pending_cuts) split.insert(ev.element);
        apply_cut_events(w);
    }
    return split;
}

/// Independent reference: a tet is fully crossed by a region of the plane x = plane_x when it
/// straddles the plane and every straddling edge meets the plane inside the region.
template <class Inside>
std::set<int> crossed_inside(const World& w, double plane_x, Inside inside_region) {
    std::set<int> out;
    for (int e = 0; e < w.mesh_elements; ++e) {
        bool straddles = false, inside = true;
        for (const auto& ed : kTetEdges) {
            const Vec3 a = w.nodes.rest[w.elements.nodes[e][ed[0]]], b = w.nodes.rest[w.elements.nodes[e][ed[1]]];
            if ((a.x() - plane_x) * (b.x() - plane_x) >= 0) continue;
            straddles = true;
            inside = inside && inside_region(Vec3(a + (plane_x - a.x()) / (b.x() - a.x()) * (b - a)));
        }
        if (straddles && inside) out.insert(e);
    }
    return out;
}

/// The swept rectangle x = plane_x, y in [y0, y1] (the blade spans the thickness).
std::set<int> expected_split(const World& w, double y0, double y1, double plane_x = kX) {
    return crossed_inside(w, plane_x, [&](const Vec3& q) { return q.y() >= y0 && q.y() <= y1; });
}

TEST(CutSystem, StraightIncisionSplitsExactlyTheCrossedElements) {
    World w = slab_with_scalpel({key(0.0, kX, 0.003), key(1.0, kX, 0.017)});
    const std::set<int> split = run_cutter(w, 1.2, 0.01);
    const std::set<int> expected = expected_split(w, 0.003, 0.017);
    EXPECT_EQ(expected.size(), 7u * 6u) << "cells y in [4, 16] mm: 6 full cells of 6 tets, plus the tets of the end cells the sweep crosses completely";
    EXPECT_EQ(split, expected);
    EXPECT_EQ(w.cuts.count(), static_cast<int>(expected.size()));
}

// Two scalpels making two incisions at the same time cut independently: each splits exactly what it
// crossed, as it would alone. (With one shared crack front, the second searched around the first's
// wound and cut nothing until it reached it.)
TEST(CutSystem, TwoScalpelsCutTwoIncisionsIndependently) {
    constexpr double kX2 = 0.011;  // the second incision, also in the middle of a 2 mm cell
    World w = slab_with_scalpel({key(0.0, kX, 0.003), key(1.0, kX, 0.017)});
    add_scalpel(w, "second", {key(0.0, kX2, 0.017), key(1.0, kX2, 0.003)}, Vec3(0, 0, -0.001), Vec3(0, 0, 0.003));
    const std::set<int> split = run_cutter(w, 1.2, 0.01);
    std::set<int> expected = expected_split(w, 0.003, 0.017);
    const std::set<int> second = expected_split(w, 0.003, 0.017, kX2);
    ASSERT_GE(second.size(), 6u * 6u) << "at least the 6 inner cells";
    for (int e : second) ASSERT_EQ(expected.count(e), 0u) << "two separate incisions";
    expected.insert(second.begin(), second.end());
    EXPECT_EQ(split, expected);
    ASSERT_EQ(w.cut_state.blade.size(), 2u);
}

// The sweep of a step is cut whole: the same incision (1 s along y at x = kX) stepped at dt from
// 0.1 ms to 10 s splits the same elements. "Same" is exact here: with the body at rest the cut
// depends only on the surface the blade swept, and every dt splits exactly the elements that
// surface crosses completely (expected_split). At dt = 10 s the whole motion lies within the first
// step that moves the tool: before the ToolSystem sampled the blade within a step, it cut nothing.
TEST(CutSystem, SweepOfAStepIsCutWholeAtAnyDt) {
    for (double dt : {1e-4, 0.01, 0.1, 10.0}) {
        SCOPED_TRACE(dt);
        World w = slab_with_scalpel({key(0.0, kX, 0.003), key(1.0, kX, 0.017)});
        ElementBvh bvh;
        std::set<int> split;
        for (int n = 1;; ++n) {  // as the pipeline steps: the first moves the tool to dt; until two steps
                                 // past the end (the blade stops, its last stretch is cut)
            const double t = n * dt;
            if (t > 1.0 + 2.0 * dt) break;
            advance_tools(w, t);
            w.time = t;
            run_cut_system(w, bvh);
            for (const CutEvent& ev : w.pending_cuts) split.insert(ev.element);
            apply_cut_events(w);
        }
        EXPECT_EQ(split, expected_split(w, 0.003, 0.017));
    }
}

// The first step: a blade whose whole motion lies within it (here the first 0.05 s of a 0.1 s step)
// cuts what it passed through.
TEST(CutSystem, MotionWithinTheFirstStepIsCut) {
    World w = slab_with_scalpel({key(0.0, kX, 0.003), key(0.05, kX, 0.017)});
    ElementBvh bvh;
    std::set<int> split;
    for (int n = 1; n <= 3; ++n) {  // the pipeline's first step takes the tool from t = 0 to dt
        advance_tools(w, 0.1 * n);
        w.time = 0.1 * n;
        run_cut_system(w, bvh);
        for (const CutEvent& ev : w.pending_cuts) split.insert(ev.element);
        apply_cut_events(w);
    }
    EXPECT_EQ(split, expected_split(w, 0.003, 0.017));
}

TEST(CutSystem, TremblingBladeSplitsTheSameSet) {
    // The same path, the blade shaking back and forth along it (up to 0.6 mm back) and by 10 um
    // across it: each edge still counts once.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> back(0.0, 0.0006), across(-1e-5, 1e-5);
    std::vector<Keyframe> path;
    for (int i = 0; i <= 100; ++i) {
        const double y = 0.003 + 0.014 * i / 100.0;
        path.push_back(key(0.01 * i, kX + across(rng), std::max(0.003, y - (i % 2 ? back(rng) : 0.0))));
    }
    path.push_back(key(1.01, kX, 0.017));
    World w = slab_with_scalpel(path, 0.0004);
    const std::set<int> split = run_cutter(w, 1.2, 0.005);
    EXPECT_EQ(split, expected_split(w, 0.003, 0.017));
}

TEST(CutSystem, LongQuadsAndFastBladeMissNothing) {
    // The blade enters slowly (quads of about one element), then jumps 13 mm (six elements) in one
    // step: the neighbourhood search must grow with the quad's length.
    World w = slab_with_scalpel({key(0.0, kX, 0.001), key(0.03, kX, 0.004), key(0.04, kX, 0.017)});
    const std::set<int> split = run_cutter(w, 0.06, 0.01);
    EXPECT_GE(w.cut_state.quad_ms.size(), 2u);
    EXPECT_EQ(split, expected_split(w, 0.001, 0.017));
}

// A graded mesh, as real ones are: 0.25 mm cells along the incision, 5 mm cells beyond it. The
// search depth is sized by the mean edge (about 3 mm here), which is a dozen of the small cells: the
// search follows the swept quad's own extent instead, so every crossed element is split.
TEST(CutSystem, GradedMeshSplitsEveryCrossedElement) {
    std::array<std::vector<double>, 3> lines;
    for (int i = 0; i <= 20; ++i) lines[0].push_back(0.002 * i);
    for (int i = 0; i <= 40; ++i) lines[1].push_back(0.00025 * i);
    for (int i = 1; i <= 18; ++i) lines[1].push_back(0.01 + 0.005 * i);
    lines[2] = {0.0, 0.002};
    World w = world_from_mesh(generate_box_on_lines(lines));
    add_scalpel(w, "scalpel", {key(0.0, kX, 0.0005), key(1.0, kX, 0.0095)}, Vec3(0, 0, -0.001), Vec3(0, 0, 0.003));
    EXPECT_GT(mean_edge_length(w.elements, w.nodes.rest, w.mesh_elements), 0.0025) << "the mean edge is many of the small cells";
    const std::set<int> split = run_cutter(w, 1.2, 0.01);
    const std::set<int> expected = expected_split(w, 0.0005, 0.0095);
    EXPECT_GT(expected.size(), 100u);
    EXPECT_EQ(split, expected);
}

TEST(CutSystem, ToolThatNeverTouchesCutsNothing) {
    Keyframe a = key(0.0, kX, 0.003), b = key(1.0, kX, 0.017);
    a.position.z() = b.position.z() = 0.01;  // 1 cm above the slab
    World w = slab_with_scalpel({a, b});
    EXPECT_TRUE(run_cutter(w, 1.2, 0.01).empty());
    EXPECT_EQ(w.cuts.count(), 0);
}

TEST(CutSystem, IndependentOfThreadCount) {
    auto run = [](int threads) {
        set_thread_count(threads);
        World w = slab_with_scalpel({key(0.0, kX, 0.003), key(0.5, kX, 0.017)});
        w.gravity = Vec3(0, 0, -9.81);
        w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
        apply_constraints(w);
        ElementBvh bvh;
        for (int n = 0; n < 60; ++n) {
            advance_tools(w, w.time + w.solver.dt);
            run_cut_system(w, bvh);
            testing::step_world(w);
        }
        return w;
    };
    const World a = run(1), b = run(2);
    set_thread_count(2);
    ASSERT_EQ(a.cuts.element, b.cuts.element);
    ASSERT_EQ(a.nodes.count(), b.nodes.count());
    for (int i = 0; i < a.nodes.count(); ++i) ASSERT_EQ(a.nodes.position[i], b.nodes.position[i]) << "node " << i;
}

TEST(CutSystem, TwoDimensionalBladeSplitsTrianglesCrossedOnTwoEdges) {
    World w = world_from_mesh(generate_plate(grid({0.04, 0.02, 0}, {20, 10, 1})));
    add_scalpel(w, "scalpel", {key(0.0, kX, 0.003), key(1.0, kX, 0.017)}, Vec3::Zero(), Vec3(0, 0, 0.001));
    const std::set<int> split = run_cutter(w, 1.2, 0.01);
    std::set<int> expected;
    for (int e = 0; e < w.mesh_elements; ++e) {
        int straddling = 0, inside = 0;
        for (const auto& ed : kTriEdges) {
            const Vec3 a = w.nodes.rest[w.elements.nodes[e][ed[0]]], b = w.nodes.rest[w.elements.nodes[e][ed[1]]];
            if ((a.x() - kX) * (b.x() - kX) >= 0) continue;
            ++straddling;
            const double y = a.y() + (kX - a.x()) / (b.x() - a.x()) * (b.y() - a.y());
            inside += y >= 0.003 && y <= 0.017;
        }
        if (straddling == 2 && inside == 2) expected.insert(e);
    }
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(split, expected);
}

// An X incision on the default skin: a second scalpel across the first wound meets elements already
// cut along another plane. xcut splits an element once, and the end of the run says so, naming the
// tool; the first incision alone says nothing of the kind.
TEST(CutSystem, ABladeAcrossAnEarlierWoundIsReported) {
    const auto notes_of = [](const std::vector<std::string>& overrides, int steps, std::vector<int>& recut) {
        Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json", overrides);
        scene.visual_subdivisions = scene.collision_subdivisions = -1;
        auto sim = make_simulation(scene, false);
        for (int i = 0; i < steps; ++i) step_simulation(*sim);
        recut = sim->world.cut_state.recut_ignored;
        std::string all;
        for (const std::string& n : end_of_run_notes(sim->world)) all += n + "\n";
        return all;
    };
    std::vector<int> recut;
    const std::string one = notes_of({}, 130, recut);
    EXPECT_EQ(one.find("already cut"), std::string::npos) << one;
    const std::string x = notes_of({testing::kCrossingScalpel},
                                   210, recut);
    EXPECT_NE(x.find("tool \"cross\" crossed"), std::string::npos) << x;
    ASSERT_EQ(recut.size(), 2u);
    EXPECT_EQ(recut[0], 0) << "the first scalpel met no earlier wound";
    EXPECT_GT(recut[1], 0);
}

// A stab: a scalpel pushed point-first down along its own vertical edge into a 10 mm block. Its edge
// sweeps no surface; with a face 6 mm wide (blade.back) it splits exactly the elements the faces it
// passed through cross completely (the plane x = kX, y in [ya, ya + 6 mm], from the deepest tip
// up), an independent count like expected_split's. Without a face it splits nothing.
TEST(CutSystem, AStabCutsWhatTheBladesFacePasses) {
    const double ya = 0.0071, width = 0.006, deepest = 0.004;
    auto stab = [&](const Vec3& back) {
        World w = world_from_mesh(generate_box(grid({0.04, 0.02, 0.01}, {20, 10, 5})));
        Keyframe above = key(0.0, kX, ya), below = key(1.0, kX, ya);
        above.position.z() = 0.014, below.position.z() = deepest;
        add_scalpel(w, "scalpel", {above, below}, Vec3::Zero(), Vec3(0, 0, 0.004));
        w.tools.blade_back[0] = back;
        return std::pair{run_cutter(w, 1.2, 0.01), w};
    };
    EXPECT_TRUE(stab(Vec3::Zero()).first.empty()) << "an edge moving along itself sweeps no surface";
    const auto [split, w] = stab(Vec3(0, width, 0));
    const std::set<int> expected = crossed_inside(
        w, kX, [&](const Vec3& q) { return q.y() >= ya && q.y() <= ya + width && q.z() >= deepest; });
    EXPECT_GT(expected.size(), 10u);
    EXPECT_EQ(split, expected);
}

}  // namespace
}  // namespace xcut
