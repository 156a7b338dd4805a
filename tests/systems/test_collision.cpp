// Tool contact (paper §3.5): penalty contacts between FCL tool shapes and the mapped collision
// surface, forces spread through the XFEM shape functions, reactions fed back to the tools.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/error.h"
#include "systems/pipeline.h"
#include "systems/collision_system.h"
#include "systems/kernels/tool_shape_depth.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name, const std::string& text) {
    const fs::path d = fs::temp_directory_path() / ("xcut_collision_" + std::to_string(::getpid()));
    fs::create_directories(d);
    std::ofstream(d / name) << text;
    return d / name;
}

TEST(ToolShape, PenetrationOfEachShape) {
    ToolShape sphere;
    sphere.kind = ToolShape::kSphere, sphere.radius = 0.01;
    Penetration p = penetration(sphere, Vec3(0.003, 0.004, 0));
    EXPECT_NEAR(p.depth, 0.005, 1e-15);
    EXPECT_NEAR((p.normal - Vec3(0.6, 0.8, 0)).norm(), 0.0, 1e-15);
    sphere.centre = Vec3(0, 0, 0.05);  // centred above the tool origin, like a handle
    EXPECT_NEAR(penetration(sphere, Vec3(0.003, 0.004, 0.05)).depth, 0.005, 1e-15);
    EXPECT_LT(penetration(sphere, Vec3(0.003, 0.004, 0)).depth, 0.0);
    ToolShape capsule;
    capsule.kind = ToolShape::kCapsule, capsule.radius = 0.002, capsule.length = 0.02;
    p = penetration(capsule, Vec3(0.001, 0, 0.008));
    EXPECT_NEAR(p.depth, 0.001, 1e-15);
    EXPECT_NEAR((p.normal - Vec3::UnitX()).norm(), 0.0, 1e-15);
    EXPECT_LT(penetration(capsule, Vec3(0, 0, 0.0125)).depth, 0.0) << "beyond the end cap";
    ToolShape box;
    box.kind = ToolShape::kBox;
    box.half_extent = Vec3(0.01, 0.02, 0.03);
    p = penetration(box, Vec3(0.008, 0.0, -0.01));
    EXPECT_NEAR(p.depth, 0.002, 1e-15);
    EXPECT_NEAR((p.normal - Vec3::UnitX()).norm(), 0.0, 1e-15);
    // A closed mesh: the unit cube [0, 1]^3 as 12 outward triangles.
    ToolShape cube;
    cube.kind = ToolShape::kMesh;
    cube.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                     Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
    cube.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                      {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    p = penetration(cube, Vec3(0.5, 0.5, 0.9));
    EXPECT_NEAR(p.depth, 0.1, 1e-12);
    EXPECT_NEAR((p.normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    EXPECT_LT(penetration(cube, Vec3(0.5, 0.5, 1.2)).depth, 0.0);
}

/// A 20 x 20 x 5 mm block of the paper's tissue, free, on a 40 x 40 x 10 mm box tool whose top face
/// is the block's bottom face; gravity -z; mass damping brings it to rest.
const char* kBlockOnPlatform = R"({
  "mesh": { "generator": "box", "origin": [0, 0, 0], "size": [0.02, 0.02, 0.005], "cells": [4, 4, 2] },
  "material": { "young": 10000, "poisson": 0.3, "density": 1000 },
  "gravity": [0, 0, -9.81],
  "collision": { "subdivisions": 0 },
  "tools": [ { "name": "platform", "shape": { "type": "box", "size": [0.04, 0.04, 0.01] },
               "contact": { "stiffness": 50 },
               "trajectory": [ { "time": 0, "position": [0.01, 0.01, -0.005] } ] } ],
  "solver": { "dt": 0.01, "cg_tolerance": 1e-10, "cg_max_iterations": 500, "damping": { "mass": 8 } },
  "steps": 300
})";

// Newton's third law to round-off, and at rest the platform carries the block's weight (2 %).
TEST(Collision, PlatformCarriesTheBlocksWeight) {
    const Scene scene = load_scene(temp_file("platform.json", kBlockOnPlatform).string());
    auto sim = make_simulation(scene, false);
    World& w = sim->world;
    double weight = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) weight += w.nodes.mass[i] * 9.81;
    for (int s = 0; s < scene.steps; ++s) {
        step_simulation(*sim);
        // The contact forces as the tissue's DOF nodes receive them (spread by the weights).
        Vec3 on_tissue = Vec3::Zero();
        for (int k = 0; k < w.contacts.count(); ++k)
            for (int a = 0; a < 4; ++a) on_tissue += w.contacts.bary[k][a] * w.contacts.force[k];
        ASSERT_LE((w.tools.reaction_force[0] + on_tissue).norm(), 1e-9 * std::max(1.0, on_tissue.norm()))
            << "step " << s;
    }
    ASSERT_GT(w.contacts.count(), 0);
    EXPECT_NEAR(w.tools.reaction_force[0].z(), -weight, 0.02 * weight) << "the block's weight presses the platform";
    EXPECT_LT(std::abs(w.tools.reaction_force[0].x()) + std::abs(w.tools.reaction_force[0].y()), 0.02 * weight);
    double sink = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) sink = std::max(sink, w.nodes.rest[i].z() - w.nodes.position[i].z());
    EXPECT_GT(sink, 0.0);
    EXPECT_LT(sink, 1e-3) << "the block rests on the platform instead of falling through [m]";
}

// The same platform as a closed OBJ mesh (FCL mesh-mesh path, winding-number depth) gives the same
// contacts and reactions as the box primitive (FCL mesh-shape traversal, exact box depth).
TEST(Collision, MeshPlatformActsLikeTheBoxPlatform) {
    const fs::path obj = temp_file("platform.obj",
                                   "v -0.02 -0.02 -0.005\nv 0.02 -0.02 -0.005\nv 0.02 0.02 -0.005\nv -0.02 0.02 -0.005\n"
                                   "v -0.02 -0.02 0.005\nv 0.02 -0.02 0.005\nv 0.02 0.02 0.005\nv -0.02 0.02 0.005\n"
                                   "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                   "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n");
    nlohmann::json as_mesh = nlohmann::json::parse(kBlockOnPlatform);
    as_mesh["tools"][0]["shape"] = {{"type", "mesh"}, {"file", obj.string()}};
    as_mesh["steps"] = 60;
    nlohmann::json as_box = nlohmann::json::parse(kBlockOnPlatform);
    as_box["steps"] = 60;
    auto run = [](const nlohmann::json& j, const std::string& name) {
        const Scene scene = load_scene(temp_file(name, j.dump()).string());
        auto sim = make_simulation(scene, false);
        for (int s = 0; s < scene.steps; ++s) step_simulation(*sim);
        return std::make_pair(sim->world.contacts.count(), sim->world.tools.reaction_force[0]);
    };
    const auto [box_contacts, box_force] = run(as_box, "box_platform.json");
    const auto [mesh_contacts, mesh_force] = run(as_mesh, "mesh_platform.json");
    ASSERT_GT(box_contacts, 0);
    EXPECT_EQ(mesh_contacts, box_contacts);
    // Depths agree to round-off; 60 implicit steps amplify that to well under 1e-6 of the force.
    EXPECT_LT((mesh_force - box_force).norm(), 1e-6 * box_force.norm());
}

/// A 40 x 10 x 10 mm bar clamped at both ends and cut through at x = 21.9 mm; a capsule (radius 1
/// mm, axis along y) presses 0.4 mm into the top of the left lip, on the cut elements' left side.
/// No gravity.
const char* kProbeOnLip = R"({
  "mesh": { "generator": "box", "origin": [0, 0, 0], "size": [0.04, 0.01, 0.01], "cells": [8, 2, 2] },
  "material": { "young": 10000, "poisson": 0.3, "density": 1000 },
  "constraints": { "fixed_boxes": [ { "min": [-1, -1, -1], "max": [1e-9, 1, 1] },
                                    { "min": [0.039999, -1, -1], "max": [1, 1, 1] } ] },
  "cuts": [ { "time": 0, "polygon": [[0.0219, -1, -1], [0.0219, 1, -1], [0.0219, 1, 1], [0.0219, -1, 1]] } ],
  "collision": { "subdivisions": 2 },
  "tools": [ { "name": "probe", "shape": { "type": "capsule", "radius": 0.001, "length": 0.02 },
               "contact": { "stiffness": 200 },
               "trajectory": [ { "time": 0, "position": [0.0210, 0.005, 0.0106],
                                 "orientation": [0.7071067811865476, 0.7071067811865476, 0, 0] } ] } ],
  "solver": { "dt": 0.01, "cg_tolerance": 1e-10, "cg_max_iterations": 500, "damping": { "mass": 5 } },
  "steps": 40
})";

// The contact lands on the left lip's virtual elements: that lip moves, the right lip does not
// move at all (the cut goes through, so no elastic path joins them either).
/// The contacts' (tool, vertex) pairs, sorted.
std::vector<std::pair<int, int>> contact_pairs(const Contacts& c) {
    std::vector<std::pair<int, int>> p;
    for (int k = 0; k < c.count(); ++k) p.emplace_back(c.tool[k], c.vertex[k]);
    std::sort(p.begin(), p.end());
    return p;
}

// A cut can re-make the collision surface's triangles keeping their count, or add vertices: the
// kept surface BVH is rebuilt then, not refitted (FCL refits only the same mesh; an update with
// more vertices wrote past its arrays: heap corruption in the viewer under load).
TEST(Collision, SurfaceBvhFollowsAMeshThatChangedAtTheSameTriangleCount) {
    auto sim = make_simulation(load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/open_surgery.json"), false);
    World& w = sim->world;
    while (w.contacts.count() == 0 && w.step < 400) step_simulation(*sim);
    ASSERT_GT(w.contacts.count(), 0) << "a tool presses the tissue";
    auto kept = make_collision_model();
    detect_contacts(w, *kept);
    const auto before = contact_pairs(w.contacts);
    // The same surface with its vertices numbered backwards (the triangles renumbered with them: the
    // count unchanged, the contents not), then with one vertex more (a copy of the first, unused).
    SurfaceMesh& s = w.collision;
    const int n = s.vertex_count();
    std::reverse(s.position.begin(), s.position.end());
    std::reverse(s.element.begin(), s.element.end());
    std::reverse(s.bary.begin(), s.bary.end());
    std::reverse(s.side.begin(), s.side.end());
    for (auto& t : s.triangles)
        for (int& v : t) v = n - 1 - v;
    std::vector<std::pair<int, int>> expected;
    for (const auto& [tool, v] : before) expected.emplace_back(tool, n - 1 - v);
    std::sort(expected.begin(), expected.end());
    for (int pass = 0; pass < 2; ++pass) {
        ::testing::internal::CaptureStderr();  // FCL says "BVH Error!" there when it is handed a changed mesh to refit
        detect_contacts(w, *kept);
        const std::string fcl_said = ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(fcl_said.find("BVH Error"), std::string::npos) << fcl_said;
        const auto reused = contact_pairs(w.contacts);
        auto fresh = make_collision_model();
        detect_contacts(w, *fresh);
        EXPECT_EQ(reused, contact_pairs(w.contacts)) << "pass " << pass;
        EXPECT_EQ(reused, expected) << "the same points touch the tools, pass " << pass;
        s.position.push_back(s.position[0]), s.element.push_back(s.element[0]), s.bary.push_back(s.bary[0]);
        s.side.push_back(s.side[0]);
    }
}

TEST(Collision, ProbeOnOneLipMovesThatLipOnly) {
    const Scene scene = load_scene(temp_file("lip.json", kProbeOnLip).string());
    auto sim = make_simulation(scene, false);
    World& w = sim->world;
    for (int s = 0; s < scene.steps; ++s) step_simulation(*sim);
    ASSERT_GT(w.cuts.count(), 0);
    ASSERT_GT(w.contacts.count(), 0);
    int left_sign = 0;
    for (int j = 0; j < w.mesh_nodes; ++j)
        if (w.enriched.enriched[j] && w.nodes.rest[j].x() < 0.0219) left_sign = w.enriched.sign[j];
    ASSERT_NE(left_sign, 0);
    int on_virtual = 0;
    for (int k = 0; k < w.contacts.count(); ++k) {
        const int ve = w.contacts.element[k] - w.mesh_elements;
        if (ve < 0) continue;
        ++on_virtual;
        EXPECT_EQ(w.virtual_elements.side[ve], left_sign) << "contact " << k << " lands on the left lip";
    }
    EXPECT_GT(on_virtual, 0) << "contacts on the cut elements' left virtual elements";
    double left = 0.0, right = 0.0;
    const SurfaceMesh& s = w.collision;
    for (int v = 0; v < s.vertex_count(); ++v) {
        Vec3 rest = Vec3::Zero();
        for (int a = 0; a < 4; ++a) rest += s.bary[v][a] * w.nodes.rest[w.elements.nodes[s.element[v]][a]];
        const double moved = (s.position[v] - rest).norm();
        const bool on_cut = std::abs(rest.x() - 0.0219) < 1e-9;
        if (rest.x() < 0.0219 - 1e-9 || (on_cut && s.side[v] == left_sign))
            left = std::max(left, moved);
        else
            right = std::max(right, moved);
    }
    EXPECT_GT(left, 1e-4) << "the pressed lip moves [m]";
    // Unmoved up to the round-off of interpolating rest positions (1e-15 m).
    EXPECT_LT(right, 1e-15) << "the other lip is untouched: no contact force reaches it [m]";
}

TEST(Collision, BadToolShapesAreNamed) {
    const fs::path open_mesh = temp_file("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const fs::path nan_mesh = temp_file("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
    struct Case {
        std::string key, value, where, phrase;  ///< tools[0][key] = value (JSON)
    };
    const std::vector<Case> cases = {
        {"contact", R"({"stiffness": 0})", "tools[0].contact.stiffness", "must be > 0"},
        {"contact", R"({"stiffness": -5})", "tools[0].contact.stiffness", "must be > 0"},
        {"contact", R"({"damping": -1})", "tools[0].contact.damping", "must be >= 0"},
        {"shape", R"({"type": "cone"})", "tools[0].shape.type", "sphere"},
        {"shape", R"({"type": "sphere", "radius": 0})", "tools[0].shape.radius", "out of range"},
        {"shape", R"({"type": "box", "size": [1, 0, 1]})", "tools[0].shape.size", "> 0"},
        {"shape", R"({"type": "mesh", "file": ")" + open_mesh.string() + "\"}", "faces", "not closed"},
        {"shape", R"({"type": "mesh", "file": ")" + nan_mesh.string() + "\"}", "vertex 3", "NaN"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.value);
        nlohmann::json scene = nlohmann::json::parse(kProbeOnLip);
        scene["tools"][0][c.key] = nlohmann::json::parse(c.value);
        const fs::path file = temp_file("bad.json", scene.dump());
        try {
            load_scene(file.string());
            ADD_FAILURE() << "accepted";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(c.where), std::string::npos) << msg;
            EXPECT_NE(msg.find(c.phrase), std::string::npos) << msg;
        }
    }
}

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

// The shipped open-surgery scene: after the incision the retractor holds the left lip open and the
// probe dents the right one; both tools feel the tissue.
TEST(Collision, OpenSurgerySceneHoldsTheWoundOpen) {
    const Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/open_surgery.json");
    auto sim = make_simulation(scene, false);
    World& w = sim->world;
    for (int s = 0; s < scene.steps; ++s) step_simulation(*sim);
    ASSERT_GT(w.cuts.count(), 20) << "the scalpel cut";
    // How far the left lip's cut face is pulled from the incision plane x = 30 mm, near the top [m].
    const SurfaceMesh& v = w.visual;
    double left = 1.0;
    for (size_t t = 0; t < v.triangles.size(); ++t) {
        if (!v.cut_face[t]) continue;
        for (int k : v.triangles[t]) {
            if (v.position[k].z() < 0.004) continue;
            if (v.side[k] == 0) continue;
            if (v.position[k].x() < 0.03) left = std::min(left, v.position[k].x());
        }
    }
    EXPECT_LT(left, 0.03 - 0.002) << "the left lip is pulled at least 2 mm aside";
    for (const Vec3& x : w.nodes.position) ASSERT_TRUE(x.allFinite());
    double max_disp = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) max_disp = std::max(max_disp, (w.nodes.position[i] - w.nodes.rest[i]).norm());
    EXPECT_LT(max_disp, 0.01) << "nothing flies off [m]";
    const int retractor = 1, probe = 2;
    EXPECT_GT(w.tools.reaction_force[retractor].x(), 0.01) << "the pulled lip pulls the retractor back [N]";
    EXPECT_GT(w.tools.reaction_force[probe].z(), 0.01) << "the pressed lip pushes the probe up [N]";
}

}  // namespace
}  // namespace xcut
