// Every input has a bounded cost, and what is refused names the bound; node indices in a scene mean
// the mesh file's numbering; mesh messages name what the file holds (docs/errors.md).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "engine/error.h"
#include "engine/io/mesh_io.h"
#include "engine/io/scene.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

class InputBounds : public ::testing::Test {
protected:
    void SetUp() override { dir_ = testing::temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name()); }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& text) {
        const std::string path = (dir_ / name).string();
        std::ofstream(path, std::ios::binary) << text;
        return path;
    }
    /// A scene on a small generated box with `extra` fields after the mesh.
    std::string scene(const std::string& extra) {
        return write("scene.json", R"({"mesh": {"generator": "box", "size": [0.02, 0.01, 0.01], "cells": [2, 1, 1]})" +
                                       extra + "}");
    }
    static std::string error_of(const std::function<void()>& f) {
        try {
            f();
        } catch (const InputError& e) {
            return e.what();
        }
        return "(no error)";
    }
    fs::path dir_;
};

// A scene of 200,000 nested arrays took 24 GB (the parser kept a field path per level): it is
// refused at the nesting bound, naming it.
TEST_F(InputBounds, DeepNestingIsRefusedAtTheBound) {
    const std::string deep = std::string(200000, '[') + std::string(200000, ']');
    const std::string path = write("deep.json", "{\"name\": " + deep + "}");
    const std::string msg = error_of([&] { load_scene(path); });
    EXPECT_NE(msg.find("nested more than 64 levels deep"), std::string::npos) << msg.substr(0, 300);
    EXPECT_NE(msg.find("deep.json: name"), std::string::npos) << msg.substr(0, 300);
    EXPECT_LT(msg.size(), 2000u) << "the field path is cut at the bound";
}

// An object of many keys is read in linear time (keys hashed) and a repeated key still named.
TEST_F(InputBounds, ManyKeysAndARepeatedOne) {
    std::string keys;
    for (int i = 0; i < 100000; ++i) keys += fmt::format("\"k{}\": {}, ", i, i);
    const std::string path = write("keys.json", "{\"camera\": {" + keys + "\"k7\": 1}}");
    EXPECT_NE(error_of([&] { load_scene(path); }).find("camera.k7: the key is given twice"), std::string::npos);
}

TEST_F(InputBounds, StringsListsAndCountsHaveBounds) {
    const std::string long_name = std::string(5000, 'a');
    EXPECT_NE(error_of([&] { load_scene(scene(", \"name\": \"" + long_name + "\"")); })
                  .find("name: is 5000 characters long, above the limit of 4096"),
              std::string::npos);
    EXPECT_NE(error_of([&] { load_scene(scene(", \"name\": \"" + std::string(200, 'b') + "\"")); })
                  .find("above the limit of 128 (it names the output files)"),
              std::string::npos);
    EXPECT_NE(error_of([&] { load_scene(scene(", \"name\": \"../elsewhere\"")); }).find("no '/'"), std::string::npos);
    std::string tools;
    for (int i = 0; i < 65; ++i) tools += std::string(i ? "," : "") + "{}";
    EXPECT_NE(error_of([&] { load_scene(scene(", \"tools\": [" + tools + "]")); })
                  .find("tools: holds 65 entries, above the limit of 64"),
              std::string::npos);
    EXPECT_NE(error_of([&] { load_scene(scene(", \"duration\": 1e6, \"solver\": {\"dt\": 1e-6}")); })
                  .find("duration: is 1e+12 steps of solver.dt 1e-06 s, above the limit of 100000000 steps"),
              std::string::npos);
    EXPECT_NE(error_of([&] { load_scene(scene(", \"allow\": [\"everything\"]")); })
                  .find("allow[0]: \"everything\" is not a check (known: units, young"),
              std::string::npos);
    // A scene file larger than the bound is refused before it is read.
    const std::string big = write("big.json", "{\"description\": \"" + std::string(kMaxSceneBytes, 'x') + "\"}");
    EXPECT_NE(error_of([&] { load_scene(big); }).find("above the 16777216 bytes a scene file may have"), std::string::npos);
}

// A box whose element size is tiny is refused by the element count, not by a guard that blames an
// origin of 0.
TEST_F(InputBounds, TinyElementSizeBlamesTheCountNotTheOrigin) {
    const std::string path = write("tiny.json", R"({"mesh": {"generator": "box", "size": [0.1, 0.1, 0.1], "element_size": 1e-7}})");
    const std::string msg = error_of([&] { load_scene(path); });
    EXPECT_NE(msg.find("mesh.element_size: gives"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("origin"), std::string::npos) << msg;
}

// A legacy VTK mesh with an unused node (file index 1): "fixed_nodes" count the file's nodes, the
// dropped one is said to be unused, and the world keeps each node's file index for the output.
TEST_F(InputBounds, FixedNodesCountTheFilesNodes) {
    write("tet.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 6 double\n"
                     "0 0 0\n9 9 9\n0.01 0 0\n0 0.01 0\n0 0 0.01\n0.01 0.01 0.01\n"
                     "CELLS 2 10\n4 0 2 3 4\n4 2 5 3 4\nCELL_TYPES 2\n10\n10\n");
    const auto world_with = [&](const std::string& fixed) {
        const std::string path = write("s.json", R"({"mesh": {"file": "tet.vtk"}, "constraints": {"fixed_nodes": [)" + fixed + "]}}");
        return build_world(load_scene(path));
    };
    World w = world_with("2");
    ASSERT_EQ(w.nodes.count(), 5);
    ASSERT_EQ(w.constraints.nodes.size(), 1u);
    EXPECT_EQ(w.constraints.nodes[0], 1) << "the file's node 2 is the mesh's node 1";
    EXPECT_EQ(w.nodes.rest[w.constraints.nodes[0]], Vec3(0.01, 0, 0));
    EXPECT_EQ(w.mesh_file_index, (std::vector<int>{0, 2, 3, 4, 5}));
    EXPECT_NE(error_of([&] { world_with("1"); }).find("constraints.fixed_nodes[0]: node 1 of the mesh files is used by no element"),
              std::string::npos);
    EXPECT_NE(error_of([&] { world_with("6"); }).find("node 6 does not exist (the mesh files have 6 nodes, 0 to 5)"),
              std::string::npos);
    // A node-set file counts the same way.
    write("held.txt", "5 # the far corner\n");
    const std::string sets = write("t.json", R"({"mesh": {"file": "tet.vtk"}, "constraints": {"fixed_sets": [{"file": "held.txt"}]}})");
    const World ws = build_world(load_scene(sets));
    ASSERT_EQ(ws.constraints.sets.size(), 1u);
    EXPECT_EQ(ws.constraints.sets[0].nodes, std::vector<int>{4});
}

TEST_F(InputBounds, MeshMessagesNameWhatTheFileHolds) {
    // An index beyond the file's nodes is said with the file's count (4), not the count left after
    // the unused node is dropped (3).
    const std::string out_of_range = write("range.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                                        "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\nCELLS 1 5\n4 0 1 2 7\n"
                                                        "CELL_TYPES 1\n10\n");
    const std::string range = error_of([&] { read_mesh_file(out_of_range, 0.0); });
    EXPECT_NE(range.find("node index 7 is out of range (the file has 4 nodes"), std::string::npos) << range;
    // Binary data where a keyword belongs (a short POINTS count): escaped, and the likely cause said.
    std::string binary = "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 double\n";
    const double xyz[6] = {0, 0, 0, 1, 0, 0};
    binary.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
    const std::string bytes = error_of([&] { read_mesh_file(write("short.vtk", binary), 0.0); });
    EXPECT_NE(bytes.find("binary data"), std::string::npos) << bytes;
    EXPECT_NE(bytes.find("is smaller than the data that follows"), std::string::npos) << bytes;
    for (const char c : bytes) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << "a raw byte " << int(c) << " in: " << bytes;
    // A NaN in a TetGen .node is reported against the .node.
    write("nan.node", "4 3 0 0\n0 0 0 0\n1 nan 0 0\n2 0 1 0\n3 0 0 1\n");
    write("nan.ele", "1 4 0\n0 0 1 2 3\n");
    const std::string nan = error_of([&] { read_mesh_file((dir_ / "nan.ele").string(), 0.0); });
    EXPECT_NE(nan.find("nan.node"), std::string::npos) << nan;
    EXPECT_NE(nan.find("NaN or infinite"), std::string::npos) << nan;
    // Six elements with id 44: the inverted one is named among them.
    const std::string gmsh = write("dup.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
                                              "4 0 0 1\n5 1 1 1\n$EndNodes\n$Elements\n2\n44 4 2 0 1 1 2 3 4\n44 4 2 0 1 3 2 4 5\n"
                                              "$EndElements\n");
    const std::string dup = error_of([&] { read_mesh_file(gmsh, 0.0); });
    EXPECT_NE(dup.find("element 44 (the file gives 2 elements that id: this is number 2 of them, cells[1]"), std::string::npos)
        << dup;
    // An XML VTU saved as .vtk is read by its content.
    const std::string vtu = write("grid.vtk", R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="4" NumberOfCells="1">
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
<Cells><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 3</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">4</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">10</DataArray></Cells>
</Piece></UnstructuredGrid></VTKFile>
)");
    const MeshData m = read_mesh_file(vtu, 0.0);
    EXPECT_EQ(m.cells.size(), 1u);
    ASSERT_FALSE(m.notes.empty());
    EXPECT_NE(m.notes[0].find("read as XML VTK (.vtu) by its content"), std::string::npos) << m.notes[0];
}

}  // namespace
}  // namespace xcut
