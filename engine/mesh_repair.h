#pragma once
// What a scene may ask of a mesh it reads, and the repairs every reader's mesh gets: the unit scale
// and placement (scene fields mesh.units/scale, translate, rotate), inverted cells flipped on request
// (mesh.reorient), and nodes no cell uses dropped. Each repair is said in MeshData::notes with its
// count; nothing is changed silently.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>

#include "engine/mesh_data.h"

namespace xcut {

struct MeshPlacement {
    double scale = 1.0;                                      ///< file units -> metres (units "cm": 0.01)
    bool units_given = false;                                ///< the scene said "units" or "scale"
    Eigen::Vector3d rotate_deg = Eigen::Vector3d::Zero();    ///< about x, then y, then z [degrees]
    Eigen::Vector3d translate = Eigen::Vector3d::Zero();     ///< after scale and rotation [m]
    bool reorient = false;                                   ///< flip cells of negative orientation
    /// The cell-data array that gives each cell's region (VTK files); empty: the first of
    /// kRegionArrayNames the file has, if any.
    std::string region_array;
};

/// The region a scene names by `key`: a name the mesh gives a region (Gmsh $PhysicalNames), else a
/// number; nothing when it is neither. Whether cells are in it is the caller's to check.
std::optional<int> region_tag(const std::map<int, std::string>& names, const std::string& key);
/// "m" -> 1, "cm" -> 0.01, "mm" -> 0.001: a length unit to metres (the units a scene or xcut mesh accepts).
double units_to_metres(const std::string& units);

/// Cell-data arrays taken as regions when the scene names none: meshio's Gmsh physical groups,
/// ParaView's and VTK's usual names.
inline const char* const kRegionArrayNames[] = {"gmsh:physical", "CellEntityIds", "MaterialIds", "region", "Region"};

/// Sets MeshData::cell_region from a one-component, integer-valued cell-data array: `name`, or the
/// first of kRegionArrayNames present when `name` is empty. Throws InputError when a named array is
/// missing or is not integer-valued.
void regions_from_cell_data(MeshData& mesh, const std::string& name);

/// x -> R (scale x) + translate, with R = Rz Ry Rx. A mirror-free map: orientations are kept.
void place_mesh(MeshData& mesh, const MeshPlacement& placement);
/// Flips every cell of negative signed volume (area in 2D) by swapping its last two nodes; returns
/// how many, and adds a note when any.
long long reorient_cells(MeshData& mesh);
/// Drops nodes no cell uses (they would be massless and unconstrained) and renumbers the cells;
/// returns how many, and adds a note when any.
long long drop_unused_nodes(MeshData& mesh);

}  // namespace xcut
