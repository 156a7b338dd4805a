// The run's output files as ParaView reads them: the volume and surface VTUs of a cut multi-region
// scene are read by VTK's own XML reader (tests/engine/io/read_vtu_summary.py, Debian's python3-vtk9)
// in both encodings (binary appended zlib, the default, and ASCII): the arrays, their units, the
// regions, the stress and the wound's faces are there; and xcut's reader reads its own files back.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/io/clipped_cells.h"
#include "engine/io/mesh_io.h"
#include "tests/test_helpers.h"
#include "engine/io/output.h"
#include "engine/io/scene.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

nlohmann::json vtk_summary(const std::string& vtu, const fs::path& dir) {
    const std::string json = (dir / "summary.json").string();
    const std::string cmd = fmt::format("{} {}/tests/engine/io/read_vtu_summary.py '{}' > '{}' 2>&1", XCUT_MESH_PYTHON,
                                        XCUT_SOURCE_DIR, vtu, json);
    const int rc = std::system(cmd.c_str());
    std::ifstream in(json);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(rc, 0) << text;
    return nlohmann::json::parse(text, nullptr, false);
}

class OutputFiles : public ::testing::TestWithParam<bool> {};

TEST_P(OutputFiles, VtkReadsTheArraysOfACutMultiRegionScene) {
    const bool ascii = GetParam();
    const fs::path dir = fs::temp_directory_path() / fmt::format("xcut_output_{}_{}", ::getpid(), ascii);
    fs::create_directories(dir);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/layered_incision.json");
    scene.solver.dt = 0.026;
    scene.solver.cg_tolerance = 1e-4;
    scene.output.directory = dir.string();
    scene.output.ascii = ascii;
    auto sim = make_simulation(scene, false);
    for (int i = 0; i < 50; ++i) step_simulation(*sim);
    const World& w = sim->world;
    ASSERT_GT(w.cuts.count(), 0);
    write_vtu(w, (dir / "volume.vtu").string());
    write_surface_vtu(w, (dir / "surface.vtu").string());

    const nlohmann::json v = vtk_summary((dir / "volume.vtu").string(), dir);
    ASSERT_FALSE(v.is_discarded());
    const ClippedCells shown = clipped_cells(w);
    const int cells = static_cast<int>(shown.cells.size());
    EXPECT_GT(cells, w.mesh_elements - w.cuts.count() + 2 * w.cuts.count()) << "cut elements shown in clipped pieces";
    EXPECT_EQ(v["cells"], cells);
    EXPECT_EQ(v["points"], shown.position.size()) << "the nodes, then the cut points";
    const auto& cd = v["cell_data"];
    EXPECT_EQ(cd["region"]["values"], nlohmann::json::array({1, 2, 3})) << "muscle, fat, skin";
    EXPECT_EQ(cd["material"]["values"], nlohmann::json::array({0, 1, 2}));
    EXPECT_EQ(cd["side"]["values"], nlohmann::json::array({-1, 0, 1}));
    EXPECT_EQ(cd["body"]["values"], nlohmann::json::array({0}));
    EXPECT_EQ(v["point_data"]["enriched_dof"]["values"], nlohmann::json::array({0, 1, 2})) << "2: a cut point";
    EXPECT_EQ(cd["stress_Pa"]["components"], 9);
    EXPECT_GT(cd["von_mises_Pa"]["max"].get<double>(), 100.0) << "the wall is stretched by 2 mm";
    EXPECT_LT(cd["von_mises_Pa"]["max"].get<double>(), 1e6);
    EXPECT_EQ(v["point_data"]["displacement_m"]["components"], 3);
    EXPECT_NE(v["fields"]["units"].get<std::string>().find("von_mises_Pa and stress_Pa"), std::string::npos);

    const nlohmann::json s = vtk_summary((dir / "surface.vtu").string(), dir);
    ASSERT_FALSE(s.is_discarded());
    EXPECT_EQ(s["cells"], w.visual.triangles.size());
    const double cut_faces = std::count(w.visual.cut_face.begin(), w.visual.cut_face.end(), 1);
    EXPECT_GT(cut_faces, 0);
    EXPECT_EQ(s["cell_data"]["cut_face"]["sum"].get<double>(), cut_faces) << "the wound's faces are flagged";

    fs::remove_all(dir);
}

// A 2D crack tip's element is written as four triangles fanned from the tip (the crack's entry once
// per lip), made by the CrackTipDisplaySystem at the steps the output writes, and VTK reads them.
TEST(OutputFiles, ACrackTipsElementIsWrittenAsItsFan) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("xcut_output_tip_{}", ::getpid());
    fs::create_directories(dir);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/face_skin_2d.json", {"cutter.tip={}"});
    scene.output.directory = dir.string();
    auto sim = make_simulation(scene, true);
    const World& w = sim->world;
    for (int i = 0; i < 150; ++i) step_simulation(*sim);  // the blade stops inside the skin at 1.2 s
    ASSERT_EQ(w.step % w.output.every, 0);
    EXPECT_EQ(w.tips.shown_step, w.step);
    ASSERT_EQ(w.tips.shown_element.size(), 1u);
    const ClippedCells shown = clipped_cells(w);
    EXPECT_EQ(std::count(shown.element.begin(), shown.element.end(), w.tips.shown_element[0]), 4);
    write_vtu(w, (dir / "volume.vtu").string());
    const nlohmann::json v = vtk_summary((dir / "volume.vtu").string(), dir);
    ASSERT_FALSE(v.is_discarded());
    EXPECT_EQ(v["cells"], shown.cells.size());
    EXPECT_EQ(v["points"], shown.position.size());
    fs::remove_all(dir);
}

// A quadratic material's elements are written as VTK quadratic tetrahedra over the nodes and the
// mid-edge nodes, with the mean stress of each.
TEST(QuadraticOutput, ElementsAreWrittenAsQuadraticCells) {
    const fs::path dir = fs::temp_directory_path() / fmt::format("xcut_output_quadratic_{}", ::getpid());
    fs::create_directories(dir);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/cantilever.json", {"material.element=\"quadratic\""});
    auto sim = make_simulation(scene, false);
    for (int i = 0; i < 5; ++i) step_simulation(*sim);
    const World& w = sim->world;
    ASSERT_EQ(w.quadratic.count(), w.mesh_elements);
    write_vtu(w, (dir / "volume.vtu").string());
    const nlohmann::json v = vtk_summary((dir / "volume.vtu").string(), dir);
    ASSERT_FALSE(v.is_discarded());
    EXPECT_EQ(v["cells"], w.mesh_elements);
    EXPECT_EQ(v["points"], w.nodes.count()) << "corners and mid-edge nodes";
    EXPECT_EQ(v["cell_types"], nlohmann::json::array({24})) << "VTK_QUADRATIC_TETRA";
    EXPECT_GT(v["cell_data"]["von_mises_Pa"]["max"].get<double>(), 100.0) << "the beam bends under its weight";
    EXPECT_EQ(v["point_data"]["file_node"]["min"], -1) << "the mid-edge nodes are in no file";
    fs::remove_all(dir);
}

/// Sum of the cells' measures (volume; 2D area) at the current positions.
double measure(const ClippedCells& c, int dim) {
    double sum = 0.0;
    for (const auto& t : c.cells) {
        const Vec3 a = c.position[t[1]] - c.position[t[0]], b = c.position[t[2]] - c.position[t[0]];
        const double m = dim == 3 ? a.cross(b).dot(c.position[t[3]] - c.position[t[0]]) / 6.0 : 0.5 * (a.x() * b.y() - a.y() * b.x());
        EXPECT_GE(m, -1e-18) << "every piece positively oriented";
        sum += m;
    }
    return sum;
}

// Each virtual element is clipped to its side: the pieces of a cut body fill exactly its volume (two
// full-size virtual elements per cut element would count each cut element twice), in 3D and in 2D.
TEST(ClippedCells, PiecesFillTheCutBodyExactly) {
    for (int dim : {3, 2}) {
        SCOPED_TRACE(dim);
        const MeshData mesh = dim == 3 ? generate_box(testing::grid({0.02, 0.01, 0.004}, {10, 5, 2}, 0.2))
                                       : generate_plate(testing::grid({0.02, 0.01, 0.0}, {10, 5, 1}, 0.2));
        World w = testing::world_from_mesh(mesh);
        const ClippedCells before = clipped_cells(w);
        const double whole = measure(before, dim);
        const std::vector<Vec3> cut = dim == 3 ? testing::square_on_plane(Vec3(0.0103, 0.005, 0.002), Vec3(1, 0.3, 0.1), 0.05)
                                               : std::vector<Vec3>{Vec3(0.0103, -1, 0), Vec3(0.0097, 1, 0)};
        const int split = testing::cut_now(w, cut);
        ASSERT_GT(split, 5);
        const ClippedCells after = clipped_cells(w);
        const int pieces_per_side_min = 1;
        EXPECT_GE(static_cast<int>(after.cells.size()), w.mesh_elements - split + 2 * split * pieces_per_side_min);
        EXPECT_NEAR(measure(after, dim), whole, 1e-12 * whole) << "the pieces partition every cut element";
        EXPECT_GT(after.position.size(), before.position.size()) << "cut points added";
    }
}

INSTANTIATE_TEST_SUITE_P(Encodings, OutputFiles, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Ascii" : "BinaryZlib"; });

}  // namespace
}  // namespace xcut
