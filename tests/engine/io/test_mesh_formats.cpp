// The mesh readers on files written by the real programs, during the test run: Debian's gmsh (format
// 1, 2.2 and 4.1, ASCII and binary, second order) and meshio's and VTK's own writers (VTU in every
// encoding, legacy VTK 4.2 and 5.1, POLYDATA), through tests/engine/io/write_vtk_meshes.py. Every
// variant must read as the same mesh, with the same regions; and an organ model in each family loads
// unchanged into a scene and is cut.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>

#include "engine/error.h"
#include "engine/io/mesh_io.h"
#include "engine/io/scene.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

/// Three stacked layers, one physical volume each, as a skin/fat/muscle model is built in Gmsh [m].
const char* kLayersGeo = R"(SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.06, 0.04, 0.01};
Box(2) = {0, 0, 0.01, 0.06, 0.04, 0.005};
Box(3) = {0, 0, 0.015, 0.06, 0.04, 0.002};
Coherence;
Physical Volume("muscle") = {1};
Physical Volume("fat") = {2};
Physical Volume("skin") = {3};
Mesh.CharacteristicLengthMax = 0.006;
)";

/// A liver-like ellipsoid, 240 x 160 x 100 mm, centred at the origin [m].
const char* kOrganGeo = R"(SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {0.12, 0.08, 0.05}} { Volume{1}; }
Mesh.CharacteristicLengthMax = 0.03;
)";

class RealMeshFiles : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = fs::temp_directory_path() / ("xcut_real_meshes_" + std::to_string(::getpid()));
        fs::create_directories(dir_ / "vtk");
        fs::create_directories(dir_ / "organ_cm");
        std::ofstream(dir_ / "layers.geo") << kLayersGeo;
        std::ofstream(dir_ / "organ.geo") << kOrganGeo;
        for (const char* format : {"msh1", "msh22", "msh41"}) {
            gmsh(fmt::format("-3 layers.geo -format {} -o layers_{}.msh", format, format));
            gmsh(fmt::format("-3 layers.geo -format {} -bin -o layers_{}_bin.msh", format, format));
        }
        gmsh("-3 -order 2 layers.geo -format msh41 -o layers_order2.msh");
        gmsh("-3 organ.geo -format msh1 -o organ_v1.msh");
        gmsh("-3 organ.geo -format msh22 -o organ.msh");
        run(fmt::format("{} {}/tests/engine/io/write_vtk_meshes.py layers_msh22.msh vtk", XCUT_MESH_PYTHON, XCUT_SOURCE_DIR));
        run(fmt::format("{} {}/tests/engine/io/write_vtk_meshes.py organ.msh organ_cm --scale 100", XCUT_MESH_PYTHON,
                        XCUT_SOURCE_DIR));
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }

    static void gmsh(const std::string& args) { run(fmt::format("{} {}", XCUT_GMSH, args)); }
    static void run(const std::string& command) {
        const std::string log = (dir_ / "log.txt").string();
        const int rc = std::system(fmt::format("cd '{}' && {} > '{}' 2>&1", dir_.string(), command, log).c_str());
        std::ifstream in(log);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ASSERT_EQ(rc, 0) << command << "\n" << text;
    }
    static std::string at(const std::string& name) { return (dir_ / name).string(); }

    /// The same nodes (to `tol`, relative to the mesh size), cells and regions.
    static void expect_same_mesh(const MeshData& a, const MeshData& b, double tol = 0.0) {
        ASSERT_EQ(a.points.size(), b.points.size()) << b.source;
        ASSERT_EQ(a.cells.size(), b.cells.size()) << b.source;
        for (size_t i = 0; i < a.points.size(); ++i)
            ASSERT_LE((a.points[i] - b.points[i]).norm(), tol) << b.source << " point " << i;
        for (size_t e = 0; e < a.cells.size(); ++e) ASSERT_EQ(a.cells[e], b.cells[e]) << b.source << " cell " << e;
        EXPECT_EQ(a.cell_region, b.cell_region) << b.source;
    }
    static inline fs::path dir_;
};

TEST_F(RealMeshFiles, EveryGmshFormatAndEncodingReadsAsTheSameMesh) {
    const MeshData ref = read_mesh_file(at("layers_msh41.msh"), 0.0);
    EXPECT_EQ(ref.dim, 3);
    EXPECT_GT(ref.cells.size(), 300u);
    const std::map<int, std::string> names = {{1, "muscle"}, {2, "fat"}, {3, "skin"}};
    EXPECT_EQ(ref.region_names, names);
    std::set<int> regions(ref.cell_region.begin(), ref.cell_region.end());
    EXPECT_EQ(regions, (std::set<int>{1, 2, 3})) << "every tet carries its physical group";
    for (const char* f : {"layers_msh1.msh", "layers_msh1_bin.msh", "layers_msh22.msh", "layers_msh22_bin.msh",
                          "layers_msh41_bin.msh"}) {
        const MeshData m = read_mesh_file(at(f), 0.0);
        expect_same_mesh(ref, m, 1e-15);  // ASCII holds 16 digits, binary all 17
        if (std::string(f) != "layers_msh1.msh") {  // format 1 has no names
            EXPECT_EQ(m.region_names, names) << f;
        }
        EXPECT_TRUE(m.notes.empty()) << f << ": " << (m.notes.empty() ? "" : m.notes[0]);
    }
}

TEST_F(RealMeshFiles, SecondOrderTetsReadAsTheirCornersWithANote) {
    const MeshData linear = read_mesh_file(at("layers_msh41.msh"), 0.0);
    const MeshData quadratic = read_mesh_file(at("layers_order2.msh"), 0.0);
    ASSERT_EQ(quadratic.cells.size(), linear.cells.size());
    // The mid-edge nodes are dropped; the corners are the linear mesh's nodes.
    EXPECT_EQ(quadratic.points.size(), linear.points.size());
    for (size_t e = 0; e < linear.cells.size(); ++e)
        for (int a = 0; a < 4; ++a)
            ASSERT_LE((quadratic.points[quadratic.cells[e][a]] - linear.points[linear.cells[e][a]]).norm(), 1e-12);
    ASSERT_EQ(quadratic.notes.size(), 2u);
    EXPECT_NE(quadratic.notes[0].find("10-node tetrahedra (Gmsh type 11) read as linear tetrahedra"), std::string::npos)
        << quadratic.notes[0];
    EXPECT_NE(quadratic.notes[1].find("nodes no tetrahedron uses dropped"), std::string::npos) << quadratic.notes[1];
}

TEST_F(RealMeshFiles, EveryVtkEncodingReadsAsTheGmshMesh) {
    const MeshData ref = read_mesh_file(at("layers_msh22.msh"), 0.0);
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir_ / "vtk")) {
        const std::string name = entry.path().filename().string();
        if (name == "vtk_surface.vtk") continue;
        const MeshData m = read_mesh_file(entry.path().string(), 0.0);
        expect_same_mesh(ref, m, 1e-12);  // meshio's ASCII holds 12 digits
        ASSERT_FALSE(m.cell_data.empty()) << name << " keeps its cell data";
        EXPECT_EQ(m.cell_data[0].name, "gmsh:physical") << name;
        ++files;
    }
    EXPECT_EQ(files, 15) << "5 meshio files, 6 VTU and 4 legacy files from VTK";
}

TEST_F(RealMeshFiles, PolydataSurfaceIsTetrahedralized) {
    const MeshData m = read_mesh_file(at("vtk/vtk_surface.vtk"), 0.0);
    double volume = 0.0;
    for (const auto& c : m.cells)
        volume += (m.points[c[1]] - m.points[c[0]]).cross(m.points[c[2]] - m.points[c[0]]).dot(m.points[c[3]] - m.points[c[0]]) / 6.0;
    EXPECT_NEAR(volume, 0.06 * 0.04 * 0.017, 1e-12) << "the surface's enclosed volume, filled";
}

/// A scene on `mesh_fields` (JSON members of "mesh") with a scalpel drawn along x through the body's
/// middle at y = `y`, from x0 to x1, over 0.1 s; returns elements split after 15 steps of 10 ms.
int cut_scene(const fs::path& dir, const std::string& mesh_fields, double x0, double x1, double y, double z_lo,
              double z_hi, const std::string& extra = "") {
    const std::string scene = fmt::format(R"({{
  "mesh": {{ {} }},{}
  "material": {{ "young": 1e4, "poisson": 0.3, "density": 1000 }},
  "constraints": {{ "fixed_boxes": [ {{ "min": [-1, -1, -1], "max": [{}, 1, 1] }} ] }},
  "tools": [ {{ "name": "scalpel", "blade": {{ "tip": [0, 0, {}], "heel": [0, 0, {}] }},
               "trajectory": [ {{ "time": 0.0, "position": [{}, {}, 0] }}, {{ "time": 0.1, "position": [{}, {}, 0] }} ] }} ],
  "solver": {{ "dt": 0.01, "cg_tolerance": 1e-6 }}
}})", mesh_fields, extra, x0 - 0.3 * (x1 - x0), z_lo, z_hi, x0, y, x1, y);
    const fs::path path = dir / "scene.json";
    std::ofstream(path) << scene;
    auto sim = make_simulation(load_scene(path.string()), false);
    for (int i = 0; i < 15; ++i) step_simulation(*sim);
    return static_cast<int>(sim->world.cuts.count());
}

TEST_F(RealMeshFiles, GmshV1OrganLoadsUnchangedAndIsCut) {
    EXPECT_GT(cut_scene(dir_, R"("file": "organ_v1.msh")", -0.05, 0.05, 0.01, -0.06, 0.06), 0);
}

TEST_F(RealMeshFiles, VtuOrganInCentimetresLoadsWithItsUnitsAndIsCut) {
    const std::string file = (dir_ / "organ_cm" / "vtk_appended_zlib.vtu").string();
    MeshPlacement cm;
    cm.scale = 0.01;
    const MeshData m = read_mesh_file(file, 0.0, cm);
    Eigen::Vector3d hi = Eigen::Vector3d::Constant(-1e9);
    for (const auto& p : m.points) hi = hi.cwiseMax(p);
    EXPECT_NEAR(hi.x(), 0.12, 2e-3) << "the 24 cm organ is 0.24 m long, not 24 m";
    EXPECT_GT(cut_scene(dir_, fmt::format(R"("file": "{}", "units": "cm")", file), -0.05, 0.05, 0.01, -0.06, 0.06), 0);
}

TEST_F(RealMeshFiles, BinaryGmsh41LayersGetTheirRegionMaterialsAndAreCut) {
    const std::string materials = R"(
  "region_materials": { "fat": { "name": "fat", "young": 3e3, "poisson": 0.45, "density": 920 },
                        "3": { "name": "skin", "young": 5e4 } },)";
    EXPECT_GT(cut_scene(dir_, R"("file": "layers_msh41_bin.msh")", 0.02, 0.04, 0.02, -0.001, 0.03, materials), 0);
    // The materials land on the cells of their regions.
    std::ofstream(dir_ / "regions.json") << R"({ "mesh": { "file": "layers_msh41_bin.msh" },)" << materials
                                         << R"( "material": { "young": 2e4 } })";
    const Scene scene = load_scene((dir_ / "regions.json").string());
    const World w = build_world(scene);
    const MeshData mesh = read_mesh_file(at("layers_msh41_bin.msh"), 0.0);
    ASSERT_EQ(w.materials.list.size(), 3u);
    for (size_t e = 0; e < mesh.cells.size(); ++e) {
        const Material& m = w.materials.list[w.elements.material[e]];
        const int r = mesh.cell_region[e];
        EXPECT_EQ(m.young, r == 2 ? 3e3 : r == 3 ? 5e4 : 2e4) << "cell " << e << " region " << r;
        if (r == 3) {
            EXPECT_EQ(m.poisson, 0.3) << "a field left out comes from the scene's material";
        }
    }
    // A region the mesh does not have is named with the ones it has.
    std::ofstream(dir_ / "bad_region.json") << R"({ "mesh": { "file": "layers_msh41_bin.msh" },
      "region_materials": { "liver": { "young": 1e3 } } })";
    try {
        build_world(load_scene((dir_ / "bad_region.json").string()));
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "region_materials.liver");
        EXPECT_NE(e.message().find("its regions: 1 \"muscle\""), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace xcut
