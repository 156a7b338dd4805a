#include "engine/io/mesh_io.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>

#include "engine/error.h"

namespace xcut {

namespace fs = std::filesystem;

MeshData read_mesh_file(const std::string& path, double max_volume) {
    fs::path p(path);
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    MeshData mesh;
    if (ext == ".msh") {
        mesh = read_gmsh(path);
    } else if (ext == ".node" || ext == ".ele") {
        mesh = read_tetgen(p.replace_extension(".node").string(), fs::path(path).replace_extension(".ele").string());
    } else if (ext == ".obj" || ext == ".stl") {
        mesh = read_surface_tetrahedralize(path, max_volume);
    } else {
        throw InputError(path, "mesh.file", fmt::format("unknown mesh format \"{}\" (use .msh, .node/.ele, .obj, .stl)", ext));
    }
    validate_mesh(mesh);
    return mesh;
}

}  // namespace xcut
