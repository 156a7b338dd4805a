// The run's output files as ParaView reads them: the volume and surface VTUs of a cut multi-region
// scene are read by VTK's own XML reader (tests/engine/io/read_vtu_summary.py, Debian's python3-vtk9)
// in both encodings (binary appended zlib, the default, and ASCII): the arrays, their units, the
// regions, the stress and the wound's faces are there; and xcut's reader reads its own files back.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "engine/io/cell_stress.h"
#include "engine/io/clipped_cells.h"
#include "engine/io/mesh_io.h"
#include "tests/test_helpers.h"
#include "engine/io/output.h"
#include "engine/io/scene.h"
#include "systems/cut/enrichment_system.h"
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

/// A quadratic bar (30 x 10 x 10 mm) cut through by an oblique plane, its DOF nodes moved by a
/// quadratic field times `scale` plus a jump on the side each stands for (displace).
struct CutQuadraticBar {
    static constexpr double L = 0.03, H = 0.01;  // [m]
    const Vec3 n = Vec3(1.0, 0.2, -0.1).normalized(), on = Vec3(0.0137, H / 2, H / 2);
    World w;
    double scale = 1.0;

    CutQuadraticBar() {
        Material m;
        m.young = 1e5, m.poisson = 0.3, m.quadratic = true;
        w = testing::world_from_mesh(generate_box(testing::grid(Vec3(L, H, H), {6, 2, 2}, 0.2)), m);
        prepare_enrichment(w);
    }
    Vec3 field(const Vec3& X, int side) const {  // [m]
        const Vec3 u(20.0 * X.x() * X.x() + 5.0 * X.y() * X.z(), 30.0 * X.x() * X.y(), 40.0 * X.x() * X.z() - 10.0 * X.y() * X.y());
        return scale * (u + side * Vec3(2e-4, -1e-4, 3e-4));
    }
    Mat3 field_gradient(const Vec3& X) const {  // d u_i / d X_k [-]
        Mat3 g;
        g << 40.0 * X.x(), 5.0 * X.z(), 5.0 * X.y(), 30.0 * X.y(), 30.0 * X.x(), 0.0, 40.0 * X.z(), -20.0 * X.y(), 40.0 * X.x();
        return scale * g;
    }
    int side_of(int d) const {  // the side of the material DOF node d stands for
        const int j = d < w.mesh_nodes ? d : w.enriched.node_of_phantom[d - w.mesh_nodes];
        const int own = w.enriched.sign[j] != 0 ? w.enriched.sign[j] : (n.dot(w.nodes.rest[j] - on) > 0.0 ? 1 : -1);
        return d < w.mesh_nodes ? own : -own;
    }
    /// Cuts the bar and moves its nodes; the number of elements split.
    int cut_and_displace() {
        const int split = testing::cut_now(w, testing::square_on_plane(on, n, 0.1));
        for (int d = 0; d < w.nodes.count(); ++d) w.nodes.position[d] = w.nodes.rest[d] + field(w.nodes.rest[d], side_of(d));
        return split;
    }
};

// A cut quadratic element's pieces are quadratic tetrahedra placed by their side's 10 shape
// functions. Checked against a closed form: with every DOF node moved by a quadratic field, plus a
// jump d on the side it stands for, each point of every piece (corners, cut points, mid-edge points)
// lies at X + u(X) + side d to rounding, as a quadratic element reproduces a quadratic field (drawn
// through the corners alone, the points miss it by up to 3e-4 m here). VTK's
// reader finds quadratic tetrahedra only, and its own measure of them at rest (vtkCellSizeFilter)
// fills the bar's volume with no cell inverted: the mid-edge points are in VTK's order.
TEST(QuadraticOutput, ACutElementsPiecesAreQuadraticCellsOnTheirSidesField) {
    CutQuadraticBar bar;
    const World& w = bar.w;
    ASSERT_GT(bar.cut_and_displace(), 0);
    const ClippedCells shown = clipped_cells(w);
    int pieces = 0;
    double worst = 0.0;
    for (size_t c = 0; c < shown.cells.size(); ++c) {
        ASSERT_GE(shown.quadratic[c], 0) << "cell " << c << " of element " << shown.element[c];
        const auto dof = std::find_if(shown.cells[c].begin(), shown.cells[c].end(), [&](int p) { return p < w.nodes.count(); });
        ASSERT_NE(dof, shown.cells[c].end()) << "every piece holds a node of its side";
        const int side = bar.side_of(*dof);
        pieces += shown.element[c] >= w.mesh_elements;
        std::vector<int> points(shown.cells[c].begin(), shown.cells[c].end());
        points.insert(points.end(), shown.edge_points[shown.quadratic[c]].begin(), shown.edge_points[shown.quadratic[c]].end());
        for (int p : points)
            worst = std::max(worst, (shown.position[p] - shown.rest[p] - bar.field(shown.rest[p], side)).norm());
    }
    EXPECT_GT(pieces, 20) << "the cut elements are drawn as their clipped pieces";
    EXPECT_GT(shown.position.size(), static_cast<size_t>(w.nodes.count()) + static_cast<size_t>(pieces)) << "cut and mid-edge points";
    EXPECT_LT(worst, 1e-12) << "every point on its side's quadratic field";

    const fs::path dir = fs::temp_directory_path() / fmt::format("xcut_output_quadratic_cut_{}", ::getpid());
    fs::create_directories(dir);
    write_vtu(w, (dir / "volume.vtu").string());
    const nlohmann::json v = vtk_summary((dir / "volume.vtu").string(), dir);
    ASSERT_FALSE(v.is_discarded());
    EXPECT_EQ(v["cells"], shown.cells.size());
    EXPECT_EQ(v["cell_types"], nlohmann::json::array({24})) << "VTK_QUADRATIC_TETRA, the cut pieces too";
    const double volume = bar.L * bar.H * bar.H;
    EXPECT_NEAR(v["rest_volume"]["sum"].get<double>(), volume, 1e-12 * volume);
    EXPECT_GT(v["rest_volume"]["min"].get<double>(), 0.0);
    fs::remove_all(dir);
}

// A side's stress is the mean of its linear strain over the side: Hooke's law of the field's strain
// at the side's centroid, here computed from its clipped pieces' volumes at rest, independently of
// its quadrature rule. Small strains (1e-4), so the corotation changes it by ~1e-8; the element's
// own centroid is off by up to 18 % of the largest stress on these sides.
TEST(QuadraticOutput, ACutSidesStressIsItsStrainsMeanOverTheSide) {
    CutQuadraticBar bar;
    bar.scale = 1e-4;
    const World& w = bar.w;
    ASSERT_GT(bar.cut_and_displace(), 0);
    const ClippedCells shown = clipped_cells(w);
    std::map<int, std::pair<double, Vec3>> moments;  // per virtual element: rest volume, first moment
    for (size_t c = 0; c < shown.cells.size(); ++c) {
        if (shown.element[c] < w.mesh_elements) continue;
        const auto& t = shown.cells[c];
        const Vec3 a = shown.rest[t[0]], b = shown.rest[t[1]], d = shown.rest[t[2]], e = shown.rest[t[3]];
        const double V = (b - a).cross(d - a).dot(e - a) / 6.0;
        auto& [volume, first] = moments.try_emplace(shown.element[c], 0.0, Vec3::Zero()).first->second;
        volume += V;
        first += V * (a + b + d + e) / 4.0;
    }
    ASSERT_GT(moments.size(), 10u);
    const Material& m = w.materials.list[0];
    double worst = 0.0, largest = 0.0;
    for (const auto& [ve, moment] : moments) {
        const Mat3 grad = bar.field_gradient(moment.second / moment.first);
        const Mat3 eps = 0.5 * (grad + grad.transpose());
        const Mat3 expected = m.lambda() * eps.trace() * Mat3::Identity() + 2.0 * m.mu() * eps;
        worst = std::max(worst, (cell_cauchy_stress(w, ve) - expected).norm());
        largest = std::max(largest, expected.norm());
    }
    EXPECT_LT(worst, 1e-4 * largest);
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
