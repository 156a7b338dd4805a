#include "engine/io/mesh_io.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <string_view>

#include "engine/error.h"

namespace xcut {

namespace fs = std::filesystem;

namespace {

/// A VTK file's kind by its content, not its name: ParaView and meshio users rename files, and an
/// XML VTU saved as .vtk (or a legacy file saved as .vtu) is common. ".vtu" for XML, ".vtk" for
/// legacy; `ext` when the first bytes say neither (the reader then names what it found).
std::string sniff_vtk(const std::string& path, const std::string& ext) {
    std::ifstream in(path, std::ios::binary);
    char head[512] = {};
    in.read(head, sizeof head);
    const std::string_view text(head, static_cast<size_t>(in.gcount()));
    const size_t start = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");  // white space, a UTF-8 BOM
    if (start == std::string_view::npos) return ext;
    if (text.substr(start).rfind("# vtk DataFile", 0) == 0) return ".vtk";
    if (text[start] == '<' && text.find("<VTKFile") != std::string_view::npos) return ".vtu";
    return ext;
}

}  // namespace

MeshData read_mesh_file(const std::string& path, double max_volume, const MeshPlacement& placement) {
    fs::path p(path);
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    MeshData mesh;
    // A surface is tetrahedralized in its file's units: max_volume [m^3] is converted to them.
    const double volume_to_m3 = placement.scale * placement.scale * placement.scale;
    const double file_max_volume = max_volume / volume_to_m3;
    if (ext == ".vtk" || ext == ".vtu") {
        const std::string kind = sniff_vtk(path, ext);
        if (kind != ext)
            mesh.notes.push_back(fmt::format("read as {} by its content (its name says {})",
                                             kind == ".vtu" ? "XML VTK (.vtu)" : "legacy VTK (.vtk)", ext));
        ext = kind;
    }
    std::vector<std::string> notes = std::move(mesh.notes);
    if (ext == ".msh") {
        mesh = read_gmsh(path);
    } else if (ext == ".vtu") {
        mesh = read_vtu(path);
    } else if (ext == ".vtk") {
        mesh = read_legacy_vtk(path, file_max_volume, volume_to_m3);
    } else if (ext == ".node" || ext == ".ele") {
        mesh = read_tetgen(p.replace_extension(".node").string(), fs::path(path).replace_extension(".ele").string());
    } else if (ext == ".obj" || ext == ".stl") {
        mesh = read_surface_tetrahedralize(path, file_max_volume, 1.5, volume_to_m3);
    } else {
        throw InputError(path, "mesh.file",
                         fmt::format("unknown mesh format \"{}\" (use .msh, .vtu, .vtk, .node/.ele, .obj, .stl)", ext));
    }
    mesh.notes.insert(mesh.notes.begin(), notes.begin(), notes.end());
    if (mesh.cell_region.empty() || !placement.region_array.empty()) regions_from_cell_data(mesh, placement.region_array);
    validate_cell_indices(mesh);
    drop_unused_nodes(mesh);
    place_mesh(mesh, placement);
    if (placement.reorient) reorient_cells(mesh);
    validate_mesh(mesh);
    return mesh;
}

}  // namespace xcut
