#pragma once
// Mesh readers, one file per format: Gmsh .msh (ASCII 2.2 and 4.1; gmsh_reader.cpp), TetGen
// .node/.ele (tetgen_reader.cpp), and closed OBJ/STL surfaces (surface_reader.cpp)
// tetrahedralized with TetGen's library. Every error is an InputError naming the file and line.
#include <array>
#include <string>
#include <vector>

#include "engine/mesh_data.h"

namespace xcut {

/// A closed triangle surface read from OBJ or STL: finite vertices, every edge shared by exactly two
/// triangles (else an InputError naming the file).
struct ClosedSurface {
    std::vector<Eigen::Vector3d> points;  ///< [m]
    std::vector<std::array<int, 3>> triangles;
};
ClosedSurface read_closed_surface(const std::string& path);

MeshData read_gmsh(const std::string& path);
MeshData read_tetgen(const std::string& node_path, const std::string& ele_path);
MeshData read_surface_tetrahedralize(const std::string& path, double max_volume, double min_ratio = 1.5);
/// Dispatches on the extension (.msh, .node, .ele, .obj, .stl) and validates the result.
MeshData read_mesh_file(const std::string& path, double max_volume);

}  // namespace xcut
