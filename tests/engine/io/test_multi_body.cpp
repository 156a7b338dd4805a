// Several bodies in one scene ("bodies": [...]): skin over an organ, each with its own mesh and
// material. A body is a range of nodes and elements with a body id; one blade cuts every body it
// passes through, and the bodies do not touch each other (no deformable-deformable contact).
#include <gtest/gtest.h>

#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <set>

#include "engine/error.h"
#include "engine/io/scene.h"
#include "engine/io/scene_checks.h"
#include "systems/pipeline.h"
#include "systems/surface/surface_cut.h"
#include "tests/surface_checks.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

/// A 40 x 30 x 2 mm skin 3 mm above a 40 x 30 x 10 mm organ; a scalpel whose blade spans both cuts
/// along y at x = 21 mm.
const char* kSkinOverOrgan = R"({
  "bodies": [
    { "name": "skin", "mesh": { "generator": "box", "origin": [0, 0, 0.013], "size": [0.04, 0.03, 0.002], "element_size": 0.002 },
      "material": { "name": "skin", "young": 1e4, "poisson": 0.3 } },
    { "name": "organ", "mesh": { "generator": "box", "size": [0.04, 0.03, 0.01], "element_size": 0.0025 },
      "material": { "name": "liver", "young": 5e3, "poisson": 0.45, "density": 1060 } }
  ],
  "constraints": { "fixed_boxes": [ { "min": [-1, -1, -1], "max": [1, 1, 1e-6] },
                                    { "min": [-1, -1, 0.0129], "max": [1e-6, 1, 1] }, { "min": [0.039999, -1, 0.0129], "max": [1, 1, 1] } ] },
  "tools": [ { "name": "scalpel", "blade": { "tip": [0, 0, 0.006], "heel": [0, 0, 0.02] },
               "trajectory": [ { "time": 0, "position": [0.021, 0.004, 0] }, { "time": 0.2, "position": [0.021, 0.026, 0] } ] } ],
  "solver": { "dt": 0.01, "cg_tolerance": 1e-6 }
})";

fs::path write_scene(const std::string& name, const std::string& text) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("xcut_bodies_{}", ::getpid());
    fs::create_directories(dir);
    std::ofstream(dir / name) << text;
    return dir / name;
}

TEST(MultiBody, OneBladeCutsEveryBodyItPassesThrough) {
    const Scene scene = load_scene(write_scene("two.json", kSkinOverOrgan).string());
    auto sim = make_simulation(scene, false);
    for (int i = 0; i < 30; ++i) step_simulation(*sim);
    const World& w = sim->world;
    ASSERT_EQ(w.body_names, (std::vector<std::string>{"skin", "organ"}));
    ASSERT_EQ(w.materials.list.size(), 2u);
    EXPECT_EQ(w.materials.list[1].name, "liver");
    std::set<int> cut_bodies;
    for (int c = 0; c < w.cuts.count(); ++c) {
        const int e = w.cuts.element[c];
        cut_bodies.insert(w.elements.body[e]);
        EXPECT_EQ(w.elements.material[e], w.elements.body[e]) << "each body's cells have its material";
    }
    EXPECT_EQ(cut_bodies, (std::set<int>{0, 1})) << "the skin and the organ under it are both cut";
    // The skin's nodes come first, then the organ's: a body is a range.
    for (int e = 0; e < w.mesh_elements; ++e)
        for (int a = 0; a < 4; ++a)
            EXPECT_EQ(w.nodes.rest[w.elements.nodes[e][a]].z() > 0.0125, w.elements.body[e] == 0) << e;
}

// Skin over an organ of quadratic elements at nu 0.49: the blade cuts both, the organ's elements
// into quadratic sides (docs/elements.md, "Cutting quadratic elements"); the surfaces stay closed
// and oriented with no zero-area triangle, and every step keeps the CG tolerance.
TEST(MultiBody, ABladeCutsTheLinearSkinAndAQuadraticOrganUnderIt) {
    std::string text = kSkinOverOrgan;
    const std::string liver = R"("poisson": 0.45, "density": 1060 })";
    text.replace(text.find(liver), liver.size(), R"("poisson": 0.49, "density": 1060, "element": "quadratic" })");
    const Scene scene = load_scene(write_scene("quadratic_organ.json", text).string());
    auto sim = make_simulation(scene, false);
    for (int i = 0; i < 30; ++i) {
        step_simulation(*sim);
        EXPECT_LE(sim->world.metrics.current.cg_residual, scene.solver.cg_tolerance) << "step " << i;
    }
    const World& w = sim->world;
    ASSERT_GT(w.quadratic.count(), 0);
    std::set<int> cut_bodies;
    int quadratic_cut = 0;
    for (int c = 0; c < w.cuts.count(); ++c) {
        cut_bodies.insert(w.elements.body[w.cuts.element[c]]);
        quadratic_cut += w.quadratic.of_element[w.cuts.element[c]] >= 0;
    }
    EXPECT_EQ(cut_bodies, (std::set<int>{0, 1})) << "the skin and the organ are both cut";
    EXPECT_GT(quadratic_cut, 10);
    EXPECT_EQ(static_cast<int>(w.quadratic.side_rules.size()), 2 * quadratic_cut) << "two sides per cut element";
    int mid_phantoms = 0;
    for (int d = w.mesh_nodes; d < w.nodes.count(); ++d)
        mid_phantoms += w.enriched.node_of_phantom[d - w.mesh_nodes] >= w.quadratic.first_edge_node;
    EXPECT_GT(mid_phantoms, 0) << "the organ's mid-edge nodes on split edges have copies";
    for (int i = 0; i < w.nodes.count(); ++i) ASSERT_TRUE(w.nodes.position[i].allFinite()) << i;
    for (const SurfaceMesh* s : {&w.visual, &w.collision}) {
        testing::check_closed_oriented(*s);
        EXPECT_EQ(zero_area_triangles(*s), 0);
    }
}

TEST(MultiBody, BodiesAndATopLevelMeshAreRefusedTogether) {
    const std::string both = R"({ "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [1, 1, 1] },
      "bodies": [ { "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [1, 1, 1] } } ] })";
    try {
        load_scene(write_scene("both.json", both).string());
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "mesh");
        EXPECT_NE(e.message().find("not both"), std::string::npos) << e.what();
    }
    const std::string twice = R"({ "bodies": [
      { "name": "a", "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [1, 1, 1] } },
      { "name": "a", "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [1, 1, 1] } } ] })";
    try {
        load_scene(write_scene("twice.json", twice).string());
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "bodies[1].name");
    }
    const std::string region = R"({ "bodies": [
      { "name": "a", "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [1, 1, 1] } },
      { "name": "b", "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [1, 1, 1] },
        "region_materials": { "fat": { "young": 1e3 } } } ] })";
    try {
        build_world(load_scene(write_scene("region.json", region).string()));
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "bodies[1].region_materials.fat") << "the message names the body";
    }
}

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

// Constraints on named node sets: a region of a body's mesh (the layered wall's muscle), a sphere,
// an index file; each held on its axes.
TEST(NodeSets, RegionSphereAndFileSetsHoldTheirNodes) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("xcut_sets_{}", ::getpid());
    fs::create_directories(dir);
    std::ofstream(dir / "held.txt") << "# nodes held by index\n0 1 2\n5  # the sixth\n";
    const std::string mesh = std::string(XCUT_SOURCE_DIR) + "/scenes/meshes/abdominal_wall.msh";
    std::ofstream(dir / "sets.json") << fmt::format(R"({{
      "bodies": [ {{ "name": "wall", "mesh": {{ "file": "{}" }} }} ],
      "constraints": {{ "fixed_sets": [ {{ "region": "muscle", "body": "wall", "axes": "z" }},
                                        {{ "sphere": {{ "centre": [0.03, 0.02, 0.017], "radius": 0.006 }}, "axes": "x" }},
                                        {{ "file": "held.txt" }} ] }} }})", mesh);
    const World w = build_world(load_scene((dir / "sets.json").string()));
    int muscle = 0, sphere = 0;
    for (int e = 0; e < w.mesh_elements; ++e) {
        if (w.elements.region[e] != 1) continue;  // "muscle"
        for (int a = 0; a < 4; ++a) {
            EXPECT_TRUE(w.nodes.fixed[w.elements.nodes[e][a]] & 4);
            ++muscle;
        }
    }
    for (int i = 0; i < w.mesh_nodes; ++i) {
        const bool in_sphere = (w.nodes.rest[i] - Vec3(0.03, 0.02, 0.017)).norm() <= 0.006;
        if (in_sphere) {
            EXPECT_TRUE(w.nodes.fixed[i] & 1) << i;
            ++sphere;
        }
        const bool skin_node = w.nodes.rest[i].z() > 0.0151;  // no muscle cell reaches the skin
        if (skin_node && !in_sphere && i != 0 && i != 1 && i != 2 && i != 5) {
            EXPECT_EQ(w.nodes.fixed[i], 0) << i;
        }
    }
    EXPECT_GT(muscle, 100);
    EXPECT_GT(sphere, 3);
    for (int i : {0, 1, 2, 5}) EXPECT_EQ(w.nodes.fixed[i], 7) << "listed in held.txt";

    struct Bad {
        std::string set, field, phrase;
    };
    const Bad bad[] = {
        {R"({ "region": "bone" })", "constraints.fixed_sets[0].region", "named regions: 1 \"muscle\""},
        {R"({ "region": "muscle", "body": "liver" })", "constraints.fixed_sets[0].body", "no body is named \"liver\""},
        {R"({ "sphere": { "centre": [1, 1, 1], "radius": 0.001 } })", "constraints.fixed_sets[0].sphere", "holds no node"},
        {R"({ "region": "muscle", "sphere": { "centre": [0, 0, 0], "radius": 1 } })", "constraints.fixed_sets[0].region",
         "exactly one of"},
    };
    for (const Bad& c : bad) {
        std::ofstream(dir / "bad.json") << fmt::format(R"({{ "mesh": {{ "file": "{}" }}, "constraints": {{ "fixed_sets": [ {} ] }} }})",
                                                       mesh, c.set);
        try {
            build_world(load_scene((dir / "bad.json").string()));
            ADD_FAILURE() << c.set << ": accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.field(), c.field) << e.what();
            EXPECT_NE(e.message().find(c.phrase), std::string::npos) << e.what();
        }
    }
    std::ofstream(dir / "bad_index.txt") << "3\n4 x9\n";
    std::ofstream(dir / "bad.json") << fmt::format(R"({{ "mesh": {{ "file": "{}" }}, "constraints": {{ "fixed_sets": [ {{ "file": "bad_index.txt" }} ] }} }})", mesh);
    try {
        build_world(load_scene((dir / "bad.json").string()));
        ADD_FAILURE() << "bad index accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "line 2") << e.what();
        EXPECT_NE(e.message().find("\"x9\" is not a node index"), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace xcut
