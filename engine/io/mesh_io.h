#pragma once
// Mesh readers, one file per format: Gmsh .msh (1, 2.2 and 4.1, ASCII and binary; gmsh_reader.cpp),
// VTK XML .vtu (vtu_reader.cpp), legacy .vtk (unstructured grids, and polydata surfaces meshed by
// TetGen; legacy_vtk_reader.cpp), TetGen .node/.ele (tetgen_reader.cpp), and closed OBJ/STL surfaces
// (surface_reader.cpp) tetrahedralized with TetGen's library. Every error is an InputError naming
// the file and the line (or byte, in binary data).
#include <array>
#include <string>
#include <vector>

#include "engine/mesh_data.h"
#include "engine/mesh_repair.h"

namespace xcut {

/// A closed triangle surface read from OBJ or STL: finite vertices, every edge shared by exactly two
/// triangles (else an InputError naming the file).
struct ClosedSurface {
    std::vector<Eigen::Vector3d> points;  ///< [m]
    std::vector<std::array<int, 3>> triangles;
};
ClosedSurface read_closed_surface(const std::string& path);
/// The closedness and volume checks read_closed_surface makes, for surfaces read elsewhere (VTK).
void check_closed_surface(const std::string& path, const ClosedSurface& surface);
/// Signed volume the surface encloses (positive when outward oriented), in its units cubed.
double enclosed_volume(const ClosedSurface& surface);

MeshData read_gmsh(const std::string& path);
MeshData read_tetgen(const std::string& node_path, const std::string& ele_path);
/// `volume_to_m3`: cubic metres in a cubed file unit, so messages quote volumes in m^3.
MeshData read_surface_tetrahedralize(const std::string& path, double max_volume, double min_ratio = 1.5,
                                     double volume_to_m3 = 1.0);
/// Tetrahedralizes a closed surface (file units; max_volume in their cube, 0: no bound;
/// `volume_to_m3` as above).
MeshData tetrahedralize_surface(const std::string& path, const ClosedSurface& surface, double max_volume,
                                double min_ratio = 1.5, double volume_to_m3 = 1.0);
/// Most points TetGen may add to a surface for its quality mesh (its S switch); past it the surface
/// is refused with an InputError naming the limit. Default kMaxMeshCells / 4: a mesh at the cell
/// limit has about a fifth as many nodes. A surface with a feature far smaller than its size (a gap
/// of 1e-5 of it) asks for millions; the fuzzers lower it so that such an input is refused fast.
void set_mesher_point_limit(long long points);
long long mesher_point_limit();
/// VTK XML UnstructuredGrid: ascii, binary (base64) or appended (raw or base64), zlib-compressed or not.
MeshData read_vtu(const std::string& path);
/// Legacy VTK, ASCII or BINARY: an UNSTRUCTURED_GRID, or a POLYDATA closed surface tetrahedralized
/// like an OBJ/STL (max_volume in file units cubed).
MeshData read_legacy_vtk(const std::string& path, double max_volume, double volume_to_m3 = 1.0);
/// Dispatches on the extension (.msh, .vtu, .vtk, .node, .ele, .obj, .stl; VTK files by their
/// content, XML or legacy, whatever their name says), drops unused nodes,
/// places the mesh (units, rotation, translation), reorients if asked, and validates the result.
/// `max_volume` [m^3] bounds TetGen's tets for surfaces.
MeshData read_mesh_file(const std::string& path, double max_volume, const MeshPlacement& placement = {});

}  // namespace xcut
