#include "engine/io/mesh_io.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>

#include "engine/error.h"

namespace xcut {

namespace fs = std::filesystem;

MeshData read_mesh_file(const std::string& path, double max_volume, const MeshPlacement& placement) {
    fs::path p(path);
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    MeshData mesh;
    // A surface is tetrahedralized in its file's units: max_volume [m^3] is converted to them.
    const double file_max_volume = max_volume / (placement.scale * placement.scale * placement.scale);
    if (ext == ".msh") {
        mesh = read_gmsh(path);
    } else if (ext == ".vtu") {
        mesh = read_vtu(path);
    } else if (ext == ".vtk") {
        mesh = read_legacy_vtk(path, file_max_volume);
    } else if (ext == ".node" || ext == ".ele") {
        mesh = read_tetgen(p.replace_extension(".node").string(), fs::path(path).replace_extension(".ele").string());
    } else if (ext == ".obj" || ext == ".stl") {
        mesh = read_surface_tetrahedralize(path, file_max_volume);
    } else {
        throw InputError(path, "mesh.file",
                         fmt::format("unknown mesh format \"{}\" (use .msh, .vtu, .vtk, .node/.ele, .obj, .stl)", ext));
    }
    if (mesh.cell_region.empty() || !placement.region_array.empty()) regions_from_cell_data(mesh, placement.region_array);
    drop_unused_nodes(mesh);
    place_mesh(mesh, placement);
    if (placement.reorient) reorient_cells(mesh);
    validate_mesh(mesh);
    return mesh;
}

}  // namespace xcut
