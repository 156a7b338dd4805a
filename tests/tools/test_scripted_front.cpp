// A scripted cut's front from the scene ("cuts[i].front", systems/cut/scripted_front_system.h):
// found on the polygon, enriched after the split, and equal to the accuracy suite's enriched front
// (problem 5, checked there against CalculiX); the scenes that cannot carry one are refused by field.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>
#include <tuple>

#include "engine/error.h"
#include "engine/io/scene.h"
#include "systems/cut/crack_tip_system.h"
#include "systems/cut/scripted_front_system.h"
#include "systems/pipeline.h"
#include "systems/xfem_queries.h"
#include "tools/studies/accuracy_problems.h"

namespace xcut {
namespace scripted_front_test {
namespace {

constexpr int kLevel = 16;  ///< cells along the block's length (2.5 mm)

std::string points(const std::vector<Vec3>& polygon) {
    std::string s;
    for (const Vec3& p : polygon) s += fmt::format("{}[{:.17g}, {:.17g}, {:.17g}]", s.empty() ? "" : ", ", p.x(), p.y(), p.z());
    return s;
}

/// Problem 5's block (tools/studies/accuracy_problems.h) as a scene, cut by `polygon` at `time` [s]
/// with "front" `front` (empty: none), its elements `element`, and `cutter` (empty: the default).
struct BlockScene {
    std::string front, cutter, element = "linear";
    double time = 0.0;
};
std::string block_scene(const std::vector<Vec3>& polygon, const BlockScene& o) {
    const CutBlockSpec b;
    const Eigen::Vector3i cells = cut_block_cells(b, kLevel);
    return fmt::format(
        R"({{"name": "front", "mesh": {{"generator": "box", "size": [{}, {}, {}], "cells": [{}, {}, {}]}},
            "material": {{"young": {}, "poisson": {}, "density": {}, "element": "{}"}}, "gravity": [0, 0, 0],
            "cuts": [{{"time": {}, "polygon": [{}]{}}}], "steps": 1{}}})",
        b.size.x(), b.size.y(), b.size.z(), cells.x(), cells.y(), cells.z(), b.young, b.poisson, b.density, o.element,
        o.time, points(polygon), o.front.empty() ? "" : ", \"front\": " + o.front,
        o.cutter.empty() ? "" : ", \"cutter\": " + o.cutter);
}
std::string block_scene(const std::vector<Vec3>& polygon, const std::string& front) {
    BlockScene o;
    o.front = front;
    return block_scene(polygon, o);
}

/// The probes' displacements at the static equilibrium of world w with the block's ends pulled.
std::vector<Vec3> pulled_displacements(World& w) { return pulled_block_displacements(w, CutBlockSpec{}); }

std::string load_error(const std::string& text) {
    try {
        make_simulation(load_scene_text(text, "front.json", "."), false);
    } catch (const InputError& e) {
        return e.field() + ": " + e.message();
    }
    return "";
}

TEST(ScriptedFront, TheScenesFrontIsTheAccuracySuitesEnrichedFront) {
    const CutBlockSpec b;
    const double h = b.size.x() / kLevel;
    auto sim = make_simulation(load_scene_text(block_scene(cut_block_polygon(b), fmt::format("{{\"radius\": {}}}", 2 * h)),
                                               "front.json", "."), false);
    step_simulation(*sim);
    World& w = sim->world;
    ASSERT_EQ(w.tips.count(), 1);  // the polygon's lower edge, the only one through the tissue
    EXPECT_NEAR(w.tips.direction[0].z(), -1.0, 1e-12);  // ahead: away from the cut, down
    EXPECT_NEAR(std::abs(w.tips.tangent[0].y()), 1.0, 1e-12);
    EXPECT_NEAR(w.tips.point[0].x(), b.cut_x, 1e-15);
    EXPECT_NEAR(w.tips.point[0].z(), b.size.z() - b.depth, 1e-15);

    World api = cut_block_world(b, kLevel);  // the accuracy suite's xfem_tip row
    cut_with_polygon(api, cut_block_polygon(b));
    enrich_crack_front(api, Vec3(b.cut_x, 0, b.size.z() - b.depth), Vec3(0, 0, -1), Vec3(0, 1, 0), TipZone{2 * h});
    ASSERT_EQ(api.tips.zone(), w.tips.zone());
    const std::vector<Vec3> scene_u = pulled_displacements(w), api_u = pulled_displacements(api);
    double largest = 0.0, apart = 0.0;
    for (size_t k = 0; k < api_u.size(); ++k)
        largest = std::max(largest, api_u[k].norm()), apart = std::max(apart, (scene_u[k] - api_u[k]).norm());
    EXPECT_GT(largest, 1e-6);  // the pull opens the slit: 20 um at the ends
    EXPECT_LT(apart, 1e-6 * largest);

    World plain = cut_block_world(b, kLevel);  // without the front the lips open less (problem 5: 8.7 % short)
    cut_with_polygon(plain, cut_block_polygon(b));
    const std::vector<Vec3> plain_u = pulled_displacements(plain);
    const size_t lip = api_u.size() - 2;  // the last lip pair, deepest in the cut
    EXPECT_GT((api_u[lip + 1] - api_u[lip]).x(), 1.02 * (plain_u[lip + 1] - plain_u[lip]).x());
}

TEST(ScriptedFront, ACutAcrossTheMiddleHasTwoFrontsAndIsRefused) {
    const CutBlockSpec b;  // through the block's height, y from 1 to 4 mm: two edges inside the tissue
    const std::vector<Vec3> across = {Vec3(b.cut_x, 0.001, -0.01), Vec3(b.cut_x, 0.004, -0.01), Vec3(b.cut_x, 0.004, 0.03),
                                      Vec3(b.cut_x, 0.001, 0.03)};
    const std::string e = load_error(block_scene(across, "{\"radius\": 0}"));
    EXPECT_NE(e.find("cuts[0].front: the polygon's edges 1 and 3 both run through the tissue"), std::string::npos) << e;
}

TEST(ScriptedFront, AFrontThatEndsInsideTheTissueIsRefused) {
    const CutBlockSpec b;  // the lower edge stops at y = 3 mm, inside the 5 mm block
    std::vector<Vec3> short_edge = cut_block_polygon(b);
    short_edge[1].y() = short_edge[2].y() = 0.003;
    const std::string e = load_error(block_scene(short_edge, "{\"radius\": 0}"));
    EXPECT_NE(e.find("cuts[0].front: the polygon's edge 0 ends inside the tissue"), std::string::npos) << e;
}

TEST(ScriptedFront, APolygonOutsideTheTissueLeavesNoFront) {
    const CutBlockSpec b;
    std::vector<Vec3> above = cut_block_polygon(b);
    for (Vec3& p : above) p.z() += 0.05;
    const std::string e = load_error(block_scene(above, "{\"radius\": 0}"));
    EXPECT_NE(e.find("cuts[0].front: no edge of the polygon runs through the tissue"), std::string::npos) << e;
}

TEST(ScriptedFront, ScenesThatCannotCarryAFrontAreRefusedByField) {
    const std::vector<Vec3> poly = cut_block_polygon(CutBlockSpec{});
    const std::string front = "{\"radius\": 0.001}";
    const std::vector<std::pair<BlockScene, std::string>> refused = {
        {{front, "{\"type\": \"snap\"}"}, "XFEM's"},
        {{front, "{\"front\": \"progressive\"}"}, "\"semi\""},
        {{front, "{\"tip\": {\"radius\": 0}}"}, "cutter.tip"},
        {{front, "", "quadratic"}, "linear elements only"},
        {{front, "", "linear", 0.1}, "at rest"}};
    for (const auto& [scene, why] : refused) {
        const std::string e = load_error(block_scene(poly, scene));
        EXPECT_NE(e.find(why), std::string::npos) << e;
        if (why != "cutter.tip") {  // cutter.tip: 2D only, said first
            EXPECT_EQ(e.rfind("cuts[0].front: ", 0), 0u) << e;
        }
    }
    EXPECT_EQ(load_error(block_scene(poly, "{\"radius\": -1}")).rfind("cuts[0].front.radius", 0), 0u);
    EXPECT_EQ(load_error(block_scene(poly, "{\"radial\": 1}")).rfind("cuts[0].front", 0), 0u);
    EXPECT_EQ(load_error(block_scene(poly, front)), "");
}

/// The 2D skin patch (60 x 40 mm, 2 mm cells) cut along y = 20.1 mm from x0 to x1, its tips
/// enriched, and then the cuts `later`.
std::string plate_scene(double x0, double x1, const std::string& later = "") {
    return fmt::format(
        R"({{"name": "tips", "mesh": {{"generator": "plate", "size": [0.06, 0.04, 0], "element_size": 0.002}},
            "material": {{"young": 1e4, "poisson": 0.3, "density": 1000, "thickness": 0.002}}, "gravity": [0, 0, 0],
            "cuts": [{{"polygon": [[{}, 0.0201, 0], [{}, 0.0201, 0]], "front": {{"radius": 0.004}}}}{}], "steps": 1}})",
        x0, x1, later);
}

TEST(ScriptedFront, A2DSegmentGetsATipAtEachEndInsideTheTissue) {
    for (const auto& [x0, x1, tips] : std::vector<std::tuple<double, double, int>>{{-0.01, 0.0253, 1}, {0.0107, 0.0453, 2}}) {
        auto sim = make_simulation(load_scene_text(plate_scene(x0, x1), "tips.json", "."), false);
        step_simulation(*sim);
        const CrackTips& ct = sim->world.tips;
        ASSERT_EQ(ct.count(), tips);
        EXPECT_LT((ct.point.back() - Vec3(x1, 0.0201, 0)).norm(), 1e-15);  // the end inside, the crack behind it
        EXPECT_LT((ct.direction.back() - Vec3(1, 0, 0)).norm(), 1e-15);
        if (tips == 2) {
            EXPECT_LT((ct.point[0] - Vec3(x0, 0.0201, 0)).norm() + (ct.direction[0] + Vec3(1, 0, 0)).norm(), 1e-15);
        }
        EXPECT_GT(ct.zone(), 0);
    }
    const std::string e = load_error(plate_scene(-0.01, 0.07));
    EXPECT_EQ(e.rfind("cuts[0].front: both ends of the segment lie outside the tissue", 0), 0u) << e;
}

/// Vertex v of surface s at rest, and as its element's corners alone place it [m].
std::pair<Vec3, Vec3> vertex_rest_and_linear(const World& w, const SurfaceMesh& s, int v) {
    Vec3 X = Vec3::Zero(), x = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
        const int node = w.elements.nodes[s.element[v]][k];
        X += s.bary[v][k] * w.nodes.rest[mesh_node(w, node)], x += s.bary[v][k] * w.nodes.position[node];
    }
    return {X, x};
}

TEST(ScriptedFront, TheStepsAmplitudesPlaceTheSurfaceByTheEnrichedField) {
    auto sim = make_simulation(load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/slit_block_front.json"), false);
    for (int n = 0; n < 5; ++n) step_simulation(*sim);
    World& w = sim->world;
    const SurfaceMesh& s = w.visual;
    ASSERT_GT(s.vertex_count(), 0);
    ASSERT_EQ(w.tips.amplitude_step, w.step);  // the step's end, left by the solver's term
    const Eigen::VectorXd fresh = crack_tip_amplitudes(w);  // H factored anew at the same rotations
    ASSERT_EQ(fresh.size(), w.tips.amplitude.size());
    EXPECT_GT(fresh.norm(), 0.0);
    EXPECT_LE((fresh - w.tips.amplitude).norm(), 1e-12 * fresh.norm());

    // Every vertex at the enriched field of its element's lip (the probes' field, which problem 5
    // checks against CalculiX); the lips' vertices within a cell of the front further apart than the
    // corners alone place them.
    const Vec3 front = w.tips.point[0], normal = w.tips.direction[0].cross(w.tips.tangent[0]);
    int moved = 0;
    double worst = 0.0, opened = 0.0, linear = 0.0;
    for (int v = 0; v < s.vertex_count(); ++v) {
        const auto [X, x] = vertex_rest_and_linear(w, s, v);
        const Vec3 u = crack_enrichment_at(w, fresh, s.element[v], X, s.bary[v]);
        worst = std::max(worst, (s.position[v] - x - u).norm());
        moved += u.norm() > 1e-9;
        const Vec3 r = X - front;
        if (s.side[v] != 0 && r.dot(w.tips.direction[0]) < 0.0 && r.dot(w.tips.direction[0]) > -0.0025 &&
            std::abs(r.dot(normal)) < 1e-9) {  // a wound vertex within a cell behind the front
            const Vec3 n = s.side[v] > 0 ? normal : -normal;
            opened += (s.position[v] - X).dot(n), linear += (x - X).dot(n);
        }
    }
    EXPECT_GT(moved, 0);
    EXPECT_LT(worst, 1e-15);
    EXPECT_GT(std::abs(linear), 0.0);
    EXPECT_GT(std::abs(opened), 1.5 * std::abs(linear)) << opened << " " << linear;  // 2.3 x at 5 steps
}

TEST(ScriptedFront, ALaterCutAwayFromTheZoneLeavesItAsABuildWouldMakeIt) {
    // Across y at x = 50 mm, 25 mm ahead of the tip (zone: 4 mm), at the second step.
    auto sim = make_simulation(
        load_scene_text(plate_scene(-0.01, 0.0253, R"(, {"time": 0.001, "polygon": [[0.05, -0.01, 0], [0.05, 0.05, 0]]})"),
                        "tips.json", "."), false);
    step_simulation(*sim);
    World& w = sim->world;
    const int version = w.tips.version, cut = w.cuts.count();
    step_simulation(*sim);
    ASSERT_GT(w.cuts.count(), cut);
    EXPECT_EQ(w.tips.cuts_seen, w.cuts.count());
    EXPECT_EQ(w.tips.version, version);  // not built again
    const CrackTips kept = w.tips;
    w.tips.cuts_seen = 0;  // every cut new: the front's own reach its zone
    ASSERT_TRUE(enrich_scripted_fronts(w));
    EXPECT_GT(w.tips.version, version);
    EXPECT_EQ(w.tips.element, kept.element);
    EXPECT_EQ(w.tips.function, kept.function);
    ASSERT_EQ(w.tips.gradient.size(), kept.gradient.size());
    ASSERT_EQ(w.tips.moment.size(), kept.moment.size());
    for (size_t a = 0; a < kept.gradient.size(); ++a) EXPECT_EQ(w.tips.gradient[a], kept.gradient[a]);
    for (size_t a = 0; a < kept.moment.size(); ++a) EXPECT_EQ(w.tips.moment[a], kept.moment[a]);
}

TEST(ScriptedFront, ALaterCutThroughTheZoneBuildsItAgain) {
    // Across y at x = 28.1 mm, 2.8 mm ahead of the tip (zone: 4 mm), at the second step.
    auto sim = make_simulation(
        load_scene_text(plate_scene(-0.01, 0.0253, R"(, {"time": 0.001, "polygon": [[0.0281, -0.01, 0], [0.0281, 0.05, 0]]})"),
                        "tips.json", "."), false);
    step_simulation(*sim);
    const World& w = sim->world;
    const int zone = w.tips.zone(), version = w.tips.version, cut = w.cuts.count();
    step_simulation(*sim);
    ASSERT_GT(w.cuts.count(), cut);
    EXPECT_EQ(w.tips.cuts_seen, w.cuts.count());
    EXPECT_GT(w.tips.version, version);
    EXPECT_GT(w.tips.zone(), zone);  // the zone's elements the second cut split count twice: a part each side
    ASSERT_EQ(w.tips.count(), 1);
    for (int i = 0; i < w.nodes.count(); ++i) ASSERT_TRUE(w.nodes.position[i].allFinite());
}

}  // namespace
}  // namespace scripted_front_test
}  // namespace xcut
