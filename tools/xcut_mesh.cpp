// xcut mesh FILE: what xcut reads from a mesh file, without a scene: the format's cells, the regions
// and cell-data arrays, the bounding box in metres after --units/--scale, the quality, and every
// note a reader or a repair made. A quick way to check a SOFA, iMSTK, Gmsh or ParaView file.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "engine/io/mesh_io.h"
#include "tools/xcut_commands.h"

namespace xcut {

namespace {

void print_mesh_summary(const MeshData& mesh) {
    fmt::print("{}: {} nodes, {} {}\n", mesh.source, mesh.points.size(), mesh.cells.size(),
               mesh.dim == 3 ? "tetrahedra" : "triangles");
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& p : mesh.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    fmt::print("  bounding box [m]: ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}); size {:.4g} x {:.4g} x {:.4g}\n",
               lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z(), hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z());
    if (!mesh.cell_region.empty()) {
        std::map<int, long long> count;
        for (int r : mesh.cell_region) ++count[r];
        for (const auto& [r, n] : count) {
            const auto name = mesh.region_names.find(r);
            fmt::print("  region {}{}: {} cells\n", r, name == mesh.region_names.end() ? "" : fmt::format(" \"{}\"", name->second), n);
        }
    }
    for (const auto& a : mesh.cell_data) {
        double mn = std::numeric_limits<double>::infinity(), mx = -mn;
        for (double v : a.values) mn = std::min(mn, v), mx = std::max(mx, v);
        fmt::print("  cell data \"{}\": {} component{}, {:.6g} to {:.6g}\n", a.name, a.components, a.components == 1 ? "" : "s", mn, mx);
    }
    for (const std::string& note : mesh.notes) fmt::print("  note: {}\n", note);
}

}  // namespace

Command add_mesh_command(CLI::App& app) {
    struct Options {
        std::string file, units = "m";
        MeshPlacement placement;
        double max_volume = 0.0;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("mesh", "Read a mesh file as a scene would and print what xcut sees (no scene needed)");
    cmd->add_option("file", o->file, "Mesh file (.msh, .vtu, .vtk, .node/.ele, .obj, .stl)")->required();
    cmd->add_option("--units", o->units, "The file's length unit")->check(CLI::IsMember({"m", "cm", "mm"}));
    cmd->add_flag("--reorient", o->placement.reorient, "Flip inverted cells (reports how many)");
    cmd->add_option("--region-array", o->placement.region_array, "VTK files: the cell-data array of regions");
    cmd->add_option("--max-volume", o->max_volume, "Surfaces: TetGen's largest tetrahedron [m^3]");
    return {cmd, [o] {
                o->placement.scale = units_to_metres(o->units);
                print_mesh_summary(read_mesh_file(o->file, o->max_volume, o->placement));
                return 0;
            }};
}

}  // namespace xcut
