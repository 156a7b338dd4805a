// Scene files: every shipped scene loads; malformed scenes fail with the file, the field path and
// the reason (the command line's handling of them: tests/tools/test_cli.cpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/error.h"
#include "engine/io/scene.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& tag) {
    const fs::path d = fs::temp_directory_path() / ("xcut_scene_" + std::to_string(::getpid()) + "_" + tag);
    fs::create_directories(d);
    return d;
}

TEST(SceneLoader, EveryShippedSceneLoadsAndBuilds) {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(XCUT_SOURCE_DIR) / "scenes")) {
        if (entry.path().extension() != ".json") continue;
        SCOPED_TRACE(entry.path().string());
        const Scene scene = load_scene(entry.path().string());
        const World w = build_world(scene);
        EXPECT_GT(w.elements.count(), 100);
        EXPECT_GT(scene.steps, 0);
        const bool plate = scene.mesh.generator == "plate";
        EXPECT_EQ(w.elements.dim, plate ? 2 : 3);
        ++count;
    }
    EXPECT_GE(count, 6);  // skin_slab, slab_planar_cut, cantilever, face_skin_2d, tissue_block, hand_dorsum
}

const char* kValid = R"({
  "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [2, 2, 2] },
  "gravity": [0, 0, -9.81],
  "constraints": { "fixed_boxes": [ { "min": [-1, -1, -1], "max": [1, 1, 1e-9] } ] },
  "solver": { "dt": 0.01 },
  "steps": 3
})";

struct BadScene {
    const char* name;
    std::string patch;   ///< --set override applied to kValid, or the whole text if it starts with '!'
    const char* field;   ///< field path the message must name
    const char* phrase;  ///< reason the message must contain
};

std::vector<BadScene> bad_scenes() {
    return {
        {"invalid JSON", "!{ \"mesh\": ", "JSON", "not valid JSON"},
        {"missing mesh", "!{ \"steps\": 1 }", "mesh", "required field is missing"},
        {"file and generator", "mesh.file=\"a.msh\"", "mesh.file", "exactly one of"},
        {"typo at top level", "gravty=[0,0,0]", "gravty", "unknown field"},
        {"negative Young's modulus", "material.young=-5", "material.young", "out of range"},
        {"incompressible Poisson ratio", "material.poisson=0.5", "material.poisson", "out of range"},
        {"density as a string", "material.density=\"heavy\"", "material.density", "expected a number"},
        {"size with two components", "mesh.size=[1,1]", "mesh.size", "array of 3 numbers"},
        {"zero size", "mesh.size=[0.01,0,0.01]", "mesh.size[1]", "must be > 0"},
        {"cells out of range", "mesh.cells=[2,2,5000]", "mesh.cells[2]", "[1, 2000]"},
        {"unknown solver mode", "solver.mode=\"fast\"", "solver.mode", "is not one of"},
        {"zero time step", "solver.dt=0", "solver.dt", "out of range"},
        {"no CG iterations", "solver.cg_max_iterations=0", "solver.cg_max_iterations", "out of range"},
        {"no Newton iteration", "solver.newton.iterations=0", "solver.newton.iterations", "out of range"},
        {"box max below min", "constraints.fixed_boxes=[{\"min\":[0,0,0],\"max\":[1,-1,1]}]",
         "constraints.fixed_boxes[0].max", ">= min"},
        {"bad axes letters", "constraints.fixed_boxes=[{\"min\":[0,0,0],\"max\":[1,1,1],\"axes\":\"xw\"}]",
         "constraints.fixed_boxes[0].axes", "letters x, y, z"},
        {"fixed node beyond the mesh", "constraints.fixed_nodes=[9999]", "constraints.fixed_nodes[0]", "does not exist"},
        {"steps and duration", "duration=1.0", "duration", "not both"},
        {"2D scene with z gravity", "mesh.generator=\"plate\"", "gravity", "xy plane"},
        {"missing mesh file", "!{ \"mesh\": { \"file\": \"missing.msh\" } }", "file", "cannot open"},
        {"non-planar cut polygon", "cuts=[{\"polygon\":[[0,0,0],[1,0,0],[1,1,0],[0,1,0.5]]}]", "cuts[0].polygon[", "planar"},
        {"cut polygon on a line", "cuts=[{\"polygon\":[[0,0,0],[1,0,0],[2,0,0]]}]", "cuts[0].polygon", "zero area"},
        {"zero-length blade",
         "tools=[{\"blade\":{\"tip\":[0,0,0],\"heel\":[0,0,0]},\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}]",
         "tools[0].blade.heel", "zero length"},
        {"non-increasing trajectory times",
         "tools=[{\"blade\":{\"tip\":[0,0,0],\"heel\":[0,0,1]},\"trajectory\":[{\"time\":1,\"position\":[0,0,0]},{\"time\":1,\"position\":[1,0,0]}]}]",
         "tools[0].trajectory[1].time", "increase strictly"},
        {"zero quaternion",
         "tools=[{\"blade\":{\"tip\":[0,0,0],\"heel\":[0,0,1]},\"trajectory\":[{\"time\":0,\"position\":[0,0,0],\"orientation\":[0,0,0,0]}]}]",
         "orientation", "zero length"},
        {"bad override path", "steps.x=1", "--set steps.x", "not an object field path"},
        {"unknown cutter type", "cutter.type=\"laser\"", "cutter.type", "is not one of \"xfem\", \"snap\""},
        {"snap threshold of half an edge", "cutter.snap_threshold=0.5", "cutter.snap_threshold", "out of range (0, 0.5)"},
        {"zero snap threshold", "cutter.snap_threshold=0", "cutter.snap_threshold", "out of range (0, 0.5)"},
    };
}

TEST(SceneLoader, MalformedScenesNameFileFieldAndReason) {
    const fs::path dir = temp_dir("bad");
    int i = 0;
    for (const BadScene& c : bad_scenes()) {
        SCOPED_TRACE(c.name);
        const fs::path file = dir / ("case" + std::to_string(i++) + ".json");
        std::vector<std::string> overrides;
        if (!c.patch.empty() && c.patch[0] == '!') {
            std::ofstream(file) << c.patch.substr(1);
        } else {
            std::ofstream(file) << kValid;
            overrides.push_back(c.patch);
        }
        try {
            build_world(load_scene(file.string(), overrides));
            ADD_FAILURE() << "accepted";
        } catch (const InputError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(c.field), std::string::npos) << msg;
            EXPECT_NE(msg.find(c.phrase), std::string::npos) << msg;
            const std::string named = std::string(c.name) == "missing mesh file" ? "missing.msh" : file.filename().string();
            EXPECT_NE(msg.find(named), std::string::npos) << "names the file: " << msg;
        }
    }
    fs::remove_all(dir);
}

TEST(SceneLoader, TrajectoryCsvErrorsNameTheLine) {
    const fs::path dir = temp_dir("csv");
    std::ofstream(dir / "t.csv") << "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.1,0,nan,0,1,0,0,0\n";
    try {
        read_trajectory_csv((dir / "t.csv").string());
        ADD_FAILURE() << "accepted NaN";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("rows[1].position"), std::string::npos) << e.what();
    }
    std::ofstream(dir / "u.csv") << "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0\n";
    try {
        read_trajectory_csv((dir / "u.csv").string());
        ADD_FAILURE() << "accepted 7 columns";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
    }
    std::ofstream(dir / "ok.csv") << "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,2,0,0,0\n1,1,0,0,1,0,0,0\n";
    const auto keys = read_trajectory_csv((dir / "ok.csv").string());
    ASSERT_EQ(keys.size(), 2u);
    EXPECT_NEAR(keys[0].orientation.norm(), 1.0, 1e-15);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace xcut
