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

#include <map>
#include <numeric>

#include "components/cut_elements.h"
#include "systems/pipeline.h"
#include "systems/xfem_queries.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

/// One fragment of an element around a node: side 0 a whole element, else the cut element's side.
struct Fragment {
    int element, side;
};

int find(std::vector<int>& parent, int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
}

/// Whether fragment f has material on the face `face` (mesh nodes): a whole element everywhere, a
/// cut element's side where one of the face's nodes is on that side.
bool on_face(const World& w, const Fragment& f, const std::vector<int>& face) {
    if (f.side == 0) return true;
    for (int n : face)
        if (w.enriched.sign[n] == f.side) return true;
    return false;
}

/// The DOF node fragment f uses for mesh node j.
int dof_of(const World& w, const Fragment& f, int j) {
    if (f.side == 0) return j;
    const int c = w.cuts.cut_of_element[f.element];
    const int ve = w.virtual_elements.element[w.cuts.virtual_element[c][f.side > 0 ? 0 : 1]];
    const auto& mesh = w.elements.nodes[f.element];
    for (int a = 0; a < w.elements.nodes_per_element(); ++a)
        if (mesh[a] == j) return w.elements.nodes[ve][a];
    return -1;
}

/// Fragments around node j whose copy of j the engine and connectivity disagree on: pairs in one
/// class with different DOFs, or in two classes with one DOF.
int disagreements(const World& w, int j, std::string& first) {
    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    std::vector<Fragment> frags;
    for (int p = w.incidence.offset[j]; p < w.incidence.offset[j + 1]; ++p) {
        const int e = w.incidence.entry[p] >> 2;
        if (e >= w.mesh_elements) continue;
        if (w.cuts.cut_of_element[e] < 0) frags.push_back({e, 0});
        else frags.push_back({e, 1}), frags.push_back({e, -1});
    }
    std::vector<int> parent(frags.size());
    std::iota(parent.begin(), parent.end(), 0);
    for (size_t a = 0; a < frags.size(); ++a)
        for (size_t b = a + 1; b < frags.size(); ++b) {
            const int ea = frags[a].element, eb = frags[b].element;
            if (ea == eb) continue;
            std::vector<int> face;  // the nodes both elements hold
            for (int x = 0; x < npe; ++x)
                for (int y = 0; y < npe; ++y)
                    if (el.nodes[ea][x] == el.nodes[eb][y]) face.push_back(el.nodes[ea][x]);
            if (static_cast<int>(face.size()) != el.dim) continue;  // not a face through j (j is in both)
            const Fragment &fa = frags[a], &fb = frags[b];
            if (!on_face(w, fa, face) || !on_face(w, fb, face)) continue;
            if (fa.side != 0 && fb.side != 0 && fa.side != fb.side) continue;  // the cut's two sides
            parent[find(parent, static_cast<int>(a))] = find(parent, static_cast<int>(b));
        }
    // A progressive front's tip element: its sides are one material at a node of a split edge the
    // blade has not crossed yet (the cut's extension ahead of the blade).
    for (size_t a = 0; a + 1 < frags.size(); ++a) {
        if (frags[a].side != 1 || frags[a + 1].element != frags[a].element) continue;
        const auto& nodes = el.nodes[frags[a].element];
        for (int k = 0; k < npe; ++k)
            if (nodes[k] != j && w.enriched.sign[nodes[k]] != w.enriched.sign[j] && !edge_crossed(w, j, nodes[k]))
                parent[find(parent, static_cast<int>(a))] = find(parent, static_cast<int>(a + 1));
    }
    int bad = 0;
    for (size_t a = 0; a < frags.size(); ++a)
        for (size_t b = a + 1; b < frags.size(); ++b) {
            const bool joined = find(parent, static_cast<int>(a)) == find(parent, static_cast<int>(b));
            const bool same = dof_of(w, frags[a], j) == dof_of(w, frags[b], j);
            if (joined == same) continue;
            if (bad++ == 0)
                first = "node " + std::to_string(j) + ": element " + std::to_string(frags[a].element) + " side " +
                        std::to_string(frags[a].side) + " and element " + std::to_string(frags[b].element) + " side " +
                        std::to_string(frags[b].side) + (joined ? " connected, different DOFs" : " apart, one DOF");
        }
    return bad;
}

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
            EXPECT_EQ(disagreements(w, j, first), 0) << scene_file << " step " << step << ": " << first;
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
    expect_copies_by_connectivity("skin_slab.json", 210, 10, {R"(tools+={"name": "cross", "blade": {"tip": [0, 0, -0.003], "heel": [0, 0, 0.004]},
        "trajectory": [{"time": 0, "position": [0.016, 0.0203, 0.03]}, {"time": 1.25, "position": [0.016, 0.0203, 0.03]},
                       {"time": 1.3, "position": [0.016, 0.0203, 0]}, {"time": 2.0, "position": [0.046, 0.0203, 0]}]})"});
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
