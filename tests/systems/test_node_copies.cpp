// The copies of a node that the EnrichmentSystem makes (the real node and its phantoms) against
// material connectivity computed from scratch, the virtual node algorithm's rule (Molino, Bao &
// Fedkiw 2004): for mesh node j, each element around it holds one fragment of material (a whole
// element) or two (a cut element's sides); two fragments hold the same copy of j when their elements
// share a face through j and their parts of that face overlap. The engine keeps the copies by this
// rule incrementally (systems/cut/node_copies.cpp: only the nodes of the elements a step split or
// crossed are looked at again), so this checks that nothing it skips goes stale, on whole scenes as
// they are cut. That one cut per element gives the paper's crack-front rule is checked elsewhere,
// against the runs before the rule (GoldenRuns, bit for bit) and against hand-made cases
// (XfemCutBodies, ProgressiveFront).
#include <gtest/gtest.h>


#include "components/cut_elements.h"
#include "systems/pipeline.h"
#include "systems/xfem_queries.h"
#include "tests/node_copies_check.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

void expect_copies_by_connectivity(const std::string& scene_file, int steps, int every = 10,
                                   const std::vector<std::string>& overrides = {}) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/" + scene_file, overrides);
    scene.visual_subdivisions = scene.collision_subdivisions = -1;
    scene.output.directory.clear();
    auto sim = make_simulation(scene, false);
    const World& w = sim->world;
    int checked = 0, copies = 0;
    for (int step = 1; step <= steps; ++step) {
        step_simulation(*sim);
        if (step % every != 0 || w.cuts.count() == 0) continue;
        for (int j = 0; j < w.mesh_nodes; ++j) {
            if (!w.enriched.enriched[j]) continue;
            std::string first;
            EXPECT_EQ(testing::disagreements(w, j, first), 0) << scene_file << " step " << step << ": " << first;
            ++checked;
            copies += w.enriched.phantom[j] >= 0;
        }
    }
    EXPECT_GT(checked, 100) << "enriched nodes looked at";
    EXPECT_GT(copies, 50) << "of them with a phantom";
}

TEST(NodeCopies, TheDefaultSkinsCopiesAreItsMaterialConnectivityAtEveryStep) {
    expect_copies_by_connectivity("skin_slab.json", 200, 1);
}

// The progressive front holds a tip element's two sides together at the nodes of split edges the
// blade has not crossed: with that clause, connectivity again.
TEST(NodeCopies, AProgressiveFrontsCopiesAreItsMaterialConnectivity) {
    expect_copies_by_connectivity("skin_slab.json", 200, 5, {"cutter.front=\"progressive\""});
}

// The X incision of CutSystem.ABladeAcrossAnEarlierWoundIsReported: the second blade splits no
// element the first did, and the copies are still connectivity.
TEST(NodeCopies, AnXIncisionsCopiesAreItsMaterialConnectivity) {
    expect_copies_by_connectivity("skin_slab.json", 210, 10, {testing::kCrossingScalpel});
}

// A T: a stem from the middle of the default wound, after it. The stem's elements beside the wound
// take copies of its nodes of their own (not the wound's far lip), so the stem opens at the wound.
TEST(NodeCopies, ATIncisionsCopiesAreItsMaterialConnectivity) {
    expect_copies_by_connectivity("skin_slab.json", 210, 10, {R"(tools+={"name": "stem", "blade": {"tip": [0, 0, -0.003], "heel": [0, 0, 0.004]},
        "trajectory": [{"time": 0, "position": [0.031, 0.0203, 0.03]}, {"time": 1.25, "position": [0.031, 0.0203, 0.03]},
                       {"time": 1.3, "position": [0.031, 0.0203, 0]}, {"time": 2.0, "position": [0.046, 0.0203, 0]}]})"});
}

TEST(NodeCopies, OrganAndLayeredScenesCopiesAreTheirMaterialConnectivity) {
    expect_copies_by_connectivity("hand_dorsum.json", 300, 20);
    expect_copies_by_connectivity("layered_incision.json", 300, 10);
    expect_copies_by_connectivity("open_surgery.json", 300, 10);
}

TEST(NodeCopies, TheFaceSkinsCopiesAreItsMaterialConnectivity) { expect_copies_by_connectivity("face_skin_2d.json", 200, 5); }

}  // namespace
}  // namespace xcut
