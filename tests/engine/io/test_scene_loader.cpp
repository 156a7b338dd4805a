// Scene files: every shipped scene loads; malformed scenes fail with the file, the field path and
// the reason (the command line's handling of them: tests/tools/test_cli.cpp).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/error.h"
#include "engine/io/scene.h"
#include "engine/io/scene_checks.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

using testing::temp_dir;

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
        // A shipped scene is plausible, or says in its "allow" what it knowingly is not.
        for (const std::string& warning : plausibility_warnings(scene, w, scene.steps)) ADD_FAILURE() << warning;
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
        {"negative guess history", "solver.guess_history=-1", "solver.guess_history", "out of range"},
        {"guess history too long", "solver.guess_history=65", "solver.guess_history", "out of range"},
        {"no Newton iteration", "solver.newton.iterations=0", "solver.newton.iterations", "out of range"},
        {"box max below min", "constraints.fixed_boxes=[{\"min\":[0,0,0],\"max\":[1,-1,1]}]",
         "constraints.fixed_boxes[0].max", ">= min"},
        {"bad axes letters", "constraints.fixed_boxes=[{\"min\":[0,0,0],\"max\":[1,1,1],\"axes\":\"xw\"}]",
         "constraints.fixed_boxes[0].axes", "letters x, y, z"},
        {"fixed node beyond the mesh", "constraints.fixed_nodes=[9999]", "constraints.fixed_nodes[0]", "does not exist"},
        {"steps and duration", "duration=1.0", "duration", "not both"},
        {"2D scene with z gravity", "mesh.generator=\"plate\"", "gravity", "xy plane"},
        {"missing mesh file", "!{ \"mesh\": { \"file\": \"missing.msh\" } }", "file", "no such mesh file"},
        {"non-planar cut polygon", "cuts=[{\"polygon\":[[0,0,0],[1,0,0],[1,1,0],[0,1,0.5]]}]", "cuts[0].polygon[", "planar"},
        {"cut polygon on a line", "cuts=[{\"polygon\":[[0,0,0],[1,0,0],[2,0,0]]}]", "cuts[0].polygon", "zero area"},
        {"blade face along its edge",
         "tools=[{\"blade\":{\"tip\":[0,0,0],\"heel\":[0,0,1],\"back\":[0.01,0,0.1]},\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}]",
         "tools[0].blade.back", "within 30 degrees of the edge"},
        {"blade face of no width",
         "tools=[{\"blade\":{\"tip\":[0,0,0],\"heel\":[0,0,1],\"back\":[0,0,0]},\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}]",
         "tools[0].blade.back", "the blade's width"},
        {"blade face in 2D",
         "!{ \"mesh\": { \"generator\": \"plate\", \"size\": [0.01, 0.01, 0], \"cells\": [2, 2, 1] }, \"gravity\": [0, 0, 0], "
         "\"tools\": [{\"blade\":{\"tip\":[0,0,0],\"heel\":[0,0,1],\"back\":[0.01,0,0]},\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}] }",
         "tools[0].blade.back", "no face"},
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
        {"unknown crack front", "cutter.front=\"full\"", "cutter.front", "is not one of \"semi\", \"progressive\""},
        {"progressive front with snapping",
         "!{ \"mesh\": { \"generator\": \"box\", \"size\": [0.01, 0.01, 0.01], \"cells\": [2, 2, 2] }, "
         "\"cutter\": { \"type\": \"snap\", \"front\": \"progressive\" } }",
         "cutter.front", "needs \"type\": \"xfem\""},
        {"crack tip with snapping",
         "!{ \"mesh\": { \"generator\": \"plate\", \"size\": [0.01, 0.01, 0], \"cells\": [2, 2, 1] }, \"gravity\": [0, 0, 0], "
         "\"cutter\": { \"type\": \"snap\", \"tip\": { \"radius\": 0.001 } } }",
         "cutter.tip", "needs \"type\": \"xfem\""},
        {"crack tip on the progressive front",
         "!{ \"mesh\": { \"generator\": \"plate\", \"size\": [0.01, 0.01, 0], \"cells\": [2, 2, 1] }, \"gravity\": [0, 0, 0], "
         "\"cutter\": { \"front\": \"progressive\", \"tip\": {} } }",
         "cutter.tip", "use \"front\": \"semi\""},
        {"10-node tetrahedra with crack fronts",
         "!{ \"mesh\": { \"generator\": \"box\", \"size\": [0.01, 0.01, 0.01], \"cells\": [2, 2, 2] }, "
         "\"material\": { \"element\": \"quadratic\" }, \"cutter\": { \"tip\": {} } }",
         "material.element", "carry no crack fronts yet"},
        {"cutting again with snapping",
         "!{ \"mesh\": { \"generator\": \"box\", \"size\": [0.01, 0.01, 0.01], \"cells\": [2, 2, 2] }, "
         "\"cutter\": { \"type\": \"snap\", \"recut\": true } }",
         "cutter.recut", "linear elements without crack tips only"},
        {"cutting again as a number", "cutter.recut=1", "cutter.recut", ""},
        {"a cut drawn in an unknown frame",
         "cuts=[{\"time\":0,\"polygon\":[[0,0,0],[1,0,0],[1,1,0]],\"frame\":\"world\"}]", "cuts[0].frame",
         "is not one of \"current\", \"rest\""},
        {"negative tip radius",
         "!{ \"mesh\": { \"generator\": \"plate\", \"size\": [0.01, 0.01, 0], \"cells\": [2, 2, 1] }, \"gravity\": [0, 0, 0], "
         "\"cutter\": { \"tip\": { \"radius\": -1 } } }",
         "cutter.tip.radius", "out of range"},
        {"unknown tip field", "cutter.tip={\"size\": 1}", "cutter.tip.size", "unknown field"},
        {"a tip's stride past an edge", "cutter.tip={\"stride\": 1.5}", "cutter.tip.stride", "out of range"},
        {"unknown element", "material.element=\"cubic\"", "material.element", "is not one of \"linear\", \"quadratic\""},
        {"6-node triangles with crack tips",
         "!{ \"mesh\": { \"generator\": \"plate\", \"size\": [0.01, 0.01, 0], \"cells\": [2, 2, 1] }, \"gravity\": [0, 0, 0], "
         "\"material\": { \"element\": \"quadratic\" }, \"cutter\": { \"tip\": {} } }",
         "material.element", "carry no crack tips yet"},
        {"key given twice", "!{ \"mesh\": { \"generator\": \"box\", \"size\": [0.01, 0.01, 0.01], \"cells\": [2, 2, 2] }, "
                            "\"solver\": { \"dt\": 0.01, \"dt\": 0.02 } }",
         "solver.dt", "given twice"},
        {"key given twice in an array's object",
         "!{ \"mesh\": { \"generator\": \"box\", \"size\": [0.01, 0.01, 0.01], \"cells\": [2, 2, 2] }, "
         "\"constraints\": { \"fixed_boxes\": [ { \"min\": [0, 0, 0], \"max\": [1, 1, 1] }, "
         "{ \"min\": [0, 0, 0], \"max\": [1, 1, 1], \"min\": [0, 0, 0] } ] } }",
         "constraints.fixed_boxes[1].min", "given twice"},
        {"origin too far for the cells", "mesh.origin=[1e300,0,0]", "mesh.origin[0]", "too far from 0"},
        {"more elements than the limit", "!{ \"mesh\": { \"generator\": \"box\", \"size\": [3, 3, 3], \"element_size\": 1e-5 } }",
         "mesh.element_size", "above the limit of 4000000"},
        {"units on a generator", "mesh.units=\"cm\"", "mesh.units", "applies to a mesh file"},
        {"units and scale", "!{ \"mesh\": { \"file\": \"m.msh\", \"units\": \"cm\", \"scale\": 0.01 } }", "mesh.scale", "not both"},
        {"unknown units", "!{ \"mesh\": { \"file\": \"m.msh\", \"units\": \"inch\" } }", "mesh.units", "is not one of"},
        {"rotation beyond a turn", "!{ \"mesh\": { \"file\": \"m.msh\", \"rotate\": [0, 400, 0] } }", "mesh.rotate[1]", "[-360, 360]"},
        {"grasp opening before it closes",
         "tools=[{\"grasp\":{\"radius\":0.002,\"close\":1,\"open\":0.5},\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}]",
         "tools[0].grasp.open", "the jaws open after they close"},
        {"grasp without a reach", "tools=[{\"grasp\":{\"close\":1},\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}]",
         "tools[0].grasp.radius", "required field is missing"},
        {"grasp without a skin", "tools=[{\"grasp\":{\"radius\":0.002,\"close\":1},\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}]",
         "tools[0].grasp", "this scene has none"},
        {"grasp with the snapping cutter",
         "!{ \"mesh\": { \"generator\": \"box\", \"size\": [0.01, 0.01, 0.01], \"cells\": [2, 2, 2] }, \"visual\": "
         "{\"subdivisions\": 0}, \"cutter\": {\"type\": \"snap\"}, \"tools\": [{\"grasp\":{\"radius\":0.002,\"close\":1},"
         "\"trajectory\":[{\"time\":0,\"position\":[0,0,0]}]}] }",
         "tools[0].grasp", "needs \"cutter.type\": \"xfem\""},
        {"region material without regions", "region_materials={\"fat\":{\"young\":1e3}}", "region_materials.fat",
         "its regions: none"},
        {"region material with an unknown field", "region_materials={\"fat\":{\"stiffness\":1e3}}",
         "region_materials.fat.stiffness", "unknown field"},
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

// A scene or mesh path that is a directory is said to be one.
TEST(SceneLoader, DirectoryIsSaidToBeOne) {
    const fs::path dir = temp_dir("dirs");
    fs::create_directories(dir / "scene.json");
    fs::create_directories(dir / "liver.msh");
    std::ofstream(dir / "ok.json") << R"({ "mesh": { "file": "liver.msh" } })";
    for (const auto& [scene, expect] : {std::pair{dir / "scene.json", "scene.json: file: is a directory, not a scene file"},
                                        std::pair{dir / "ok.json", "liver.msh: file: is a directory, not a mesh file"}}) {
        try {
            build_world(load_scene(scene.string()));
            ADD_FAILURE() << "accepted " << scene;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
        }
    }
    fs::remove_all(dir);
}

/// The documented range of a material field: the fourth column of its row in docs/scene-format.md,
/// "[lo, hi]" (closed), with the Unicode minus read as '-'.
std::pair<double, double> documented_range(const std::string& key) {
    std::ifstream in(std::string(XCUT_SOURCE_DIR) + "/docs/scene-format.md");
    const std::string row = "| `" + key + "` |";
    for (std::string line; std::getline(in, line);) {
        if (line.rfind(row, 0) != 0) continue;
        for (size_t at; (at = line.find("\u2212")) != std::string::npos;) line.replace(at, 3, 1, '-');
        const size_t open = line.find('['), comma = line.find(',', open), close = line.find(']', comma);
        if (open == std::string::npos || comma == std::string::npos || close == std::string::npos) break;
        return {std::stod(line.substr(open + 1, comma - open - 1)), std::stod(line.substr(comma + 1, close - comma - 1))};
    }
    ADD_FAILURE() << "docs/scene-format.md has no closed range for " << key;
    return {0.0, 0.0};
}

// The Poisson range the docs state is the one the loader enforces: both ends load, just past them not.
TEST(SceneLoader, DocumentedPoissonRangeIsEnforced) {
    const auto [lo, hi] = documented_range("poisson");
    EXPECT_LT(lo, 0.0);
    EXPECT_LT(hi, 0.5);
    const fs::path dir = temp_dir("poisson");
    std::ofstream(dir / "s.json") << kValid;
    const auto loads = [&](double nu) {
        try {
            load_scene((dir / "s.json").string(), {fmt::format("material.poisson={:.17g}", nu)});
            return true;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("material.poisson"), std::string::npos) << e.what();
            return false;
        }
    };
    EXPECT_TRUE(loads(lo));
    EXPECT_TRUE(loads(hi));
    EXPECT_FALSE(loads(lo - 1e-6));
    EXPECT_FALSE(loads(hi + 1e-6));
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
