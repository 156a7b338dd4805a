// Mesh readers: Gmsh 2.2 / 4.1, TetGen .node/.ele, OBJ/STL surfaces through TetGen's library, and
// the bad inputs each must reject with a message naming the file and place.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/error.h"
#include "engine/io/mesh_io.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

class MeshIo : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("xcut_mesh_io_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& text) {
        const std::string p = (dir_ / name).string();
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
    /// The message of the InputError `read` throws (fails the test if none).
    template <class F>
    std::string error_of(F&& read) {
        try {
            read();
        } catch (const InputError& e) {
            return e.what();
        }
        ADD_FAILURE() << "no InputError";
        return "";
    }
    fs::path dir_;
};

const char* kGmsh22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 1 1
$EndNodes
$Elements
3
1 2 2 0 1 1 2 3
2 4 2 0 1 1 2 3 4
3 4 2 0 1 2 5 3 4
$EndElements
)";

const char* kGmsh41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
2 5 1 5
3 1 0 3
1
2
3
0 0 0
1 0 0
0 1 0
3 2 0 2
4
5
0 0 1
1 1 1
$EndNodes
$Elements
1 2 1 2
3 1 4 2
1 1 2 3 4
2 2 5 3 4
$EndElements
)";

const char* kCubeObj = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

double total_volume(const MeshData& m) {
    double v = 0.0;
    for (const auto& c : m.cells) {
        Eigen::Matrix3d D;
        for (int k = 0; k < 3; ++k) D.col(k) = m.points[c[k + 1]] - m.points[c[0]];
        EXPECT_GT(D.determinant(), 0.0);
        v += D.determinant() / 6.0;
    }
    return v;
}

TEST_F(MeshIo, GmshV2AndV4GiveTheSameMesh) {
    const MeshData a = read_mesh_file(write("a.msh", kGmsh22), 0.0);
    const MeshData b = read_mesh_file(write("b.msh", kGmsh41), 0.0);
    EXPECT_EQ(a.dim, 3);
    ASSERT_EQ(a.cells.size(), 2u);  // the surface triangle is dropped when tets exist
    EXPECT_EQ(a.points, b.points);
    EXPECT_EQ(a.cells, b.cells);
}

TEST_F(MeshIo, GmshTrianglesGiveA2DMesh) {
    const MeshData m = read_mesh_file(write("t.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n"
                                                     "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n2\n"
                                                     "1 2 0 1 2 3\n2 2 0 1 3 4\n$EndElements\n"),
                                      0.0);
    EXPECT_EQ(m.dim, 2);
    EXPECT_EQ(m.cells.size(), 2u);
}

TEST_F(MeshIo, TetgenOneAndZeroBased) {
    write("one.node", "# comment\n5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n");
    const std::string one = write("one.ele", "2 4 0\n1 1 2 3 4\n2 2 5 3 4\n");
    write("zero.node", "5 3 1 1\n0 0 0 0 7 1\n1 1 0 0 7 1\n2 0 1 0 7 1\n3 0 0 1 7 1\n4 1 1 1 7 1\n");
    const std::string zero = write("zero.ele", "2 4 1\n0 0 1 2 3 5\n1 1 4 2 3 5\n");
    const MeshData a = read_mesh_file(one, 0.0), b = read_mesh_file(zero, 0.0);
    EXPECT_EQ(a.cells, b.cells);
    EXPECT_EQ(a.points, b.points);
    EXPECT_NEAR(total_volume(a), 1.0 / 6.0 + 1.0 / 3.0, 1e-15);  // unit corner tet + (1,0,0)(1,1,1)(0,1,0)(0,0,1)
}

TEST_F(MeshIo, ObjCubeTetrahedralizedByTetgen) {
    const MeshData m = read_mesh_file(write("cube.obj", kCubeObj), 0.01);
    EXPECT_EQ(m.dim, 3);
    EXPECT_GT(m.cells.size(), 50u) << "the volume bound 0.01 m^3 forces refinement";
    EXPECT_NEAR(total_volume(m), 1.0, 1e-9);
}

TEST_F(MeshIo, AsciiStlCubeTetrahedralizedByTetgen) {
    std::string stl = "solid cube\n";
    const double v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const int tris[12][3] = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                             {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    for (const auto& t : tris) {
        stl += "facet normal 0 0 0\nouter loop\n";
        for (int k : t) stl += "vertex " + std::to_string(v[k][0]) + " " + std::to_string(v[k][1]) + " " + std::to_string(v[k][2]) + "\n";
        stl += "endloop\nendfacet\n";
    }
    stl += "endsolid cube\n";
    const MeshData m = read_mesh_file(write("cube.stl", stl), 0.0);
    EXPECT_NEAR(total_volume(m), 1.0, 1e-9);
}

struct BadCase {
    const char* name;
    const char* file;
    const char* text;
    const char* expect;  ///< phrase the message must contain
};

const BadCase kBad[] = {
    {"unknown extension", "m.xyz", "x", "unknown mesh format"},
    {"empty gmsh", "e.msh", "", "expected $MeshFormat or $NOD"},
    {"not gmsh", "ng.msh", "solid cube\n", "not a Gmsh file: it begins with \"solid\""},
    {"gmsh binary without its byte-order integer", "b.msh", "$MeshFormat\n2.2 1 8\n$EndMeshFormat\n", "byte-order integer"},
    {"gmsh binary truncated", "bt.msh", "$MeshFormat\n2.2 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n$Nodes\n2\n\x01\x00", "byte"},
    {"gmsh version 3", "v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n$Nodes\n", "format 3 is not supported"},
    {"gmsh version 4.0", "v40.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n$Nodes\n", "format 4 is not supported"},
    {"gmsh duplicate node id", "dup.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n1 1 0 0\n$EndNodes\n", "node 1 is defined twice"},
    {"gmsh v1 without elements", "v1.msh", "$NOD\n1\n1 0 0 0\n$ENDNOD\n", "no $ELM"},
    {"gmsh hexahedra only", "hex.msh",
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n$EndNodes\n"
     "$Elements\n1\n1 5 0 1 2 3 4 5 6 7 8\n$EndElements\n",
     "the file holds 1 of type 5"},
    {"vtu not xml", "x.vtu", "<VTKFile type=\"UnstructuredGrid\"><Unstructured", "not valid XML"},
    {"vtu polydata", "p.vtu", "<VTKFile type=\"PolyData\"/>", "reads UnstructuredGrid"},
    {"vtu lz4", "lz.vtu", "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkLZ4DataCompressor\"/>", "vtkLZ4DataCompressor"},
    {"vtu bad offset", "off.vtu",
     "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"1\" NumberOfCells=\"1\"><Points>"
     "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"99\"/></Points></Piece>"
     "</UnstructuredGrid><AppendedData encoding=\"raw\">_abc</AppendedData></VTKFile>",
     "offset 99 is outside the appended data"},
    {"vtu too few values", "few.vtu",
     "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"2\" NumberOfCells=\"1\"><Points>"
     "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 1</DataArray></Points></Piece>"
     "</UnstructuredGrid></VTKFile>",
     "5 values, expected 6"},
    {"vtu corrupt zlib", "z.vtu",
     "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkZLibDataCompressor\"><UnstructuredGrid><Piece NumberOfPoints=\"1\" "
     "NumberOfCells=\"1\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"binary\">"
     "AQAAAAwAAAAMAAAABAAAAA==AAAAAA==</DataArray></Points></Piece></UnstructuredGrid></VTKFile>",
     "does not inflate"},
    {"vtk not legacy", "n.vtk", "x", "not a legacy VTK file"},
    {"vtk structured points", "sp.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n", "DATASET STRUCTURED_POINTS"},
    {"vtk cells past the list", "cl.vtk",
     "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n9 0 1 2 3\n",
     "does not fit in the CELLS list"},
    {"vtk polydata open", "po.vtk",
     "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\nPOLYGONS 3 12\n3 0 2 1\n3 0 1 3\n3 1 2 3\n",
     "not closed"},
    {"gmsh missing EndNodes", "n.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$Elements\n", "expected $EndNodes"},
    {"gmsh node count too large", "c.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1000000000000\n1 0 0 0\n", "does not fit"},
    {"gmsh non-numeric coordinate", "x.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 abc 0\n$EndNodes\n", "\"abc\" is not a number"},
    {"gmsh NaN coordinate", "nan.msh",
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 nan\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n",
     "NaN or infinite"},
    {"gmsh undefined node", "u.msh",
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 9\n$EndElements\n",
     "node 9, which $Nodes does not define"},
    {"gmsh repeated node", "r.msh",
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 3\n$EndElements\n",
     "appears twice"},
    {"gmsh inverted tet", "i.msh",
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 0 1 3 2 4\n$EndElements\n",
     "is inverted"},
    {"gmsh flat tet", "f.msh",
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n",
     "degenerate"},
    {"gmsh no volume elements", "l.msh",
     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n$Elements\n1\n1 1 0 1 2\n$EndElements\n",
     "no tetrahedra"},
    {"tetgen 10-node", "q.ele", "1 10 0\n1 1 2 3 4 5 6 7 8 9 10\n", "10-node tetrahedra"},
    {"tetgen index out of range", "o.ele", "1 4 0\n1 1 2 3 7\n", "out of range"},
    {"obj open surface", "open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n", "not closed"},
    {"obj index out of range", "oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n", "out of range"},
    {"stl truncated binary", "t.stl", "", "binary STL"},
};

TEST_F(MeshIo, BadInputsAreRejectedWithTheirReason) {
    // The TetGen cases need a valid .node beside the .ele.
    write("q.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    write("o.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    for (const BadCase& c : kBad) {
        std::string text = c.text;
        if (std::string(c.file) == "t.stl") {
            text = std::string(80, ' ');
            const uint32_t n = 12;
            text.append(reinterpret_cast<const char*>(&n), 4);
            text += std::string(100, '\0');  // 2 of the 12 announced triangles
        }
        const std::string path = write(c.file, text);
        const std::string msg = error_of([&] { read_mesh_file(path, 0.0); });
        EXPECT_NE(msg.find(c.expect), std::string::npos) << c.name << ": " << msg;
        EXPECT_NE(msg.find(c.file), std::string::npos) << c.name << " names the file: " << msg;
    }
}

TEST_F(MeshIo, MissingFileIsAnError) {
    const std::string msg = error_of([&] { read_mesh_file((dir_ / "none.msh").string(), 0.0); });
    EXPECT_NE(msg.find("none.msh: file: no such mesh file"), std::string::npos) << msg;
}

// A path that is a directory is said to be one (it read as an empty Gmsh file: "no $MeshFormat").
TEST_F(MeshIo, DirectoryIsSaidToBeOne) {
    fs::create_directories(dir_ / "organ.msh");
    const std::string msg = error_of([&] { read_mesh_file((dir_ / "organ.msh").string(), 0.0); });
    EXPECT_NE(msg.find("organ.msh: file: is a directory, not a mesh file"), std::string::npos) << msg;
    // A device would be read forever.
    const std::string dev = error_of([&] { read_mesh_file("/dev/zero.msh", 0.0); });
    EXPECT_NE(dev.find("no such mesh file"), std::string::npos) << dev;
    fs::create_symlink("/dev/zero", dir_ / "zero.msh");
    const std::string zero = error_of([&] { read_mesh_file((dir_ / "zero.msh").string(), 0.0); });
    EXPECT_NE(zero.find("zero.msh: file: is not a regular file"), std::string::npos) << zero;
}

// Nodes are named by the ids the file gives them (Gmsh tags here 5, 7, 9, 11), not by their index.
TEST_F(MeshIo, NodesAreNamedAsTheFileNumbersThem) {
    const std::string nan = write("nan.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n5 0 0 nan\n7 1 0 0\n"
                                             "9 0 1 0\n11 0 0 1\n$EndNodes\n$Elements\n1\n1 4 0 5 7 9 11\n$EndElements\n");
    std::string msg = error_of([&] { read_mesh_file(nan, 0.0); });
    EXPECT_NE(msg.find("nan.msh: node 5: coordinate is NaN or infinite"), std::string::npos) << msg;
    const std::string twice = write("twice.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n5 0 0 0\n7 1 0 0\n"
                                                 "9 0 1 0\n11 0 0 1\n$EndNodes\n$Elements\n1\n1 4 0 5 7 9 9\n$EndElements\n");
    msg = error_of([&] { read_mesh_file(twice, 0.0); });
    EXPECT_NE(msg.find("node 9 appears twice"), std::string::npos) << msg;
    write("z.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 inf\n");
    const std::string ele = write("z.ele", "1 4 0\n1 1 2 3 4\n");
    msg = error_of([&] { read_mesh_file(ele, 0.0); });
    EXPECT_NE(msg.find("node 4: coordinate is NaN or infinite"), std::string::npos) << msg;
    write("inv.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    const std::string inverted = write("inv.ele", "2 4 0\n1 1 2 3 4\n2 1 3 2 4\n");
    msg = error_of([&] { read_mesh_file(inverted, 0.0); });
    EXPECT_NE(msg.find("inv.ele: element 2: is inverted"), std::string::npos) << msg;
}

}  // namespace
}  // namespace xcut

namespace xcut {
namespace {

// mesh.reorient flips inverted cells and says how many; without it, the error says it exists.
TEST_F(MeshIo, ReorientFlipsInvertedCellsAndSaysHowMany) {
    const std::string path = write("inv.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
                                              "4 0 0 1\n5 1 1 1\n$EndNodes\n$Elements\n2\n1 4 0 1 3 2 4\n2 4 0 2 5 3 4\n$EndElements\n");
    EXPECT_NE(error_of([&] { read_mesh_file(path, 0.0); }).find("mesh.reorient: true flips such cells"), std::string::npos);
    MeshPlacement p;
    p.reorient = true;
    const MeshData m = read_mesh_file(path, 0.0, p);
    ASSERT_EQ(m.notes.size(), 1u);
    EXPECT_EQ(m.notes[0], "1 inverted tetrahedra reoriented (mesh.reorient)");
    EXPECT_NEAR(total_volume(m), 1.0 / 6.0 + 1.0 / 3.0, 1e-12) << "both cells positive";
}

// A node no tet uses would be massless and freeze the solve: it is dropped, with a note.
TEST_F(MeshIo, UnusedNodeIsDroppedWithANote) {
    write("u.node", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 5 5 5\n5 0 0 1\n");
    const MeshData m = read_mesh_file(write("u.ele", "1 4 0\n1 1 2 3 5\n"), 0.0);
    ASSERT_EQ(m.points.size(), 4u);
    EXPECT_EQ(m.point_id, (std::vector<long long>{1, 2, 3, 5})) << "messages still name nodes as the file does";
    ASSERT_EQ(m.notes.size(), 1u);
    EXPECT_EQ(m.notes[0], "1 node no tetrahedron uses dropped");
    EXPECT_NEAR(total_volume(m), 1.0 / 6.0, 1e-12);
}

// Units, rotation and translation, in that order (x -> R (s x) + t).
TEST_F(MeshIo, PlacementScalesThenRotatesThenTranslates) {
    const std::string path = write("p.msh", kGmsh22);
    MeshPlacement p;
    p.scale = 0.01;
    p.rotate_deg = Eigen::Vector3d(0, 0, 90);
    p.translate = Eigen::Vector3d(1, 2, 3);
    const MeshData m = read_mesh_file(path, 0.0, p);
    const MeshData raw = read_mesh_file(path, 0.0);
    for (size_t i = 0; i < m.points.size(); ++i) {
        const Eigen::Vector3d expected(1 - 0.01 * raw.points[i].y(), 2 + 0.01 * raw.points[i].x(), 3 + 0.01 * raw.points[i].z());
        EXPECT_LE((m.points[i] - expected).norm(), 1e-15) << i;
    }
    EXPECT_NEAR(total_volume(m), 1e-6 * total_volume(raw), 1e-18) << "a rotation keeps every cell positive";
}

// A max_volume that would make more tets than the limit is refused before TetGen allocates them.
TEST_F(MeshIo, SurfaceMeshedTooFinelyIsRefusedBeforeMeshing) {
    const std::string cube = write("cube.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                               "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
    const std::string msg = error_of([&] { read_mesh_file(cube, 1e-15); });
    EXPECT_NE(msg.find("mesh.max_volume: 1e-15 m^3 would make at least 1e+15 tetrahedra, above the limit of 4000000"),
              std::string::npos) << msg;
    // A surface in millimetres: the bound is quoted in m^3, as the scene gives it, not in mm^3.
    MeshPlacement mm;
    mm.scale = 1e-3;
    const std::string in_mm = error_of([&] { read_mesh_file(cube, 1e-24, mm); });
    EXPECT_NE(in_mm.find("mesh.max_volume: 1e-24 m^3 would make at least 1e+15 tetrahedra"), std::string::npos) << in_mm;
}

}  // namespace
}  // namespace xcut
