#pragma once
// A mesh as read from a file or made by a generator, before it becomes components. Units: metres.
#include <Eigen/Core>
#include <array>
#include <map>
#include <string>
#include <vector>

namespace xcut {

/// The most cells a mesh may have: larger ones are refused before they are allocated (a mesh of
/// 4 million tets needs about 20 GB in xcut with a Cholesky factor; docs/scene-format.md).
inline constexpr long long kMaxMeshCells = 4'000'000;

struct MeshData {
    int dim = 3;                                 ///< 3: tetrahedra; 2: triangles in the xy plane (z = 0)
    std::vector<Eigen::Vector3d> points;         ///< [m]
    std::vector<std::array<int, 4>> cells;       ///< node indices; triangles use the first three, [3] = -1
    std::string source;                          ///< file name or generator name, for messages
    /// The file the points come from, where it is not `source` (TetGen's .node beside its .ele).
    std::string points_source;
    /// The ids the file gives its nodes and cells (Gmsh tags, TetGen indices), for messages; empty:
    /// the mesh numbers them itself, and messages name points[i] and cells[i].
    std::vector<long long> point_id, cell_id;
    /// Each point's index in the file's own order (0-based), kept when unused nodes are dropped, so
    /// that a scene's node indices and the output's "file_node" array mean the file's numbering;
    /// empty: points[i] is the file's point i. `file_points`: how many points the file lists.
    std::vector<int> file_index;
    long long file_points = -1;  ///< -1: points.size()
    /// Region of each cell: a Gmsh physical group, a TetGen region attribute, or a VTK cell-data
    /// array the scene names; empty when the file has none. 0 is "no region".
    std::vector<int> cell_region;
    std::map<int, std::string> region_names;  ///< names the file gives regions (Gmsh $PhysicalNames)
    /// Cell data as read (VTU/VTK arrays), one value per cell and component, for regions and materials.
    struct CellArray {
        std::string name;
        int components = 1;
        std::vector<double> values;  ///< cells x components, row-major
    };
    std::vector<CellArray> cell_data;
    /// What the reader read differently from the file or repaired (second-order cells read as their
    /// corners, unused nodes dropped, cells reoriented): said once each, as a warning, by the caller.
    std::vector<std::string> notes;

    int nodes_per_cell() const { return dim == 3 ? 4 : 3; }
    /// How a message names point i and cell e: as the file numbers them.
    std::string point_name(size_t i) const;
    std::string cell_name(size_t e) const;
};

/// Signed volume of cell `c` (2D: signed area in the xy plane) at `mesh.points` [m^3 or m^2];
/// positive when its nodes are in the positive order. Indices are assumed valid.
double signed_cell_measure(const MeshData& mesh, const std::array<int, 4>& c);

/// Throws InputError naming the cell when a cell refers to a node the file does not have (checked
/// before unused nodes are dropped, so the count quoted is the file's).
void validate_cell_indices(const MeshData& mesh);

/// Rejects meshes the physics cannot run on: no cells, NaN/inf coordinates, out-of-range or repeated
/// indices, inverted or zero-volume (zero-area) cells. Cells of negative orientation are not
/// silently flipped: the file is wrong, and the message says which cell. Throws InputError naming
/// `mesh.source` and the cell. `rel_tol`: a cell whose volume is below rel_tol * (longest edge)^dim
/// is degenerate.
void validate_mesh(const MeshData& mesh, double rel_tol = 1e-12);

}  // namespace xcut
