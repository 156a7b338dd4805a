#include "engine/mesh_repair.h"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <climits>
#include <cmath>
#include <cstdlib>

#include "engine/error.h"

namespace xcut {

void place_mesh(MeshData& mesh, const MeshPlacement& p) {
    const double deg = EIGEN_PI / 180.0;
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(p.rotate_deg.z() * deg, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(p.rotate_deg.y() * deg, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(p.rotate_deg.x() * deg, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    for (Eigen::Vector3d& x : mesh.points) x = R * (p.scale * x) + p.translate;
}

std::optional<int> region_tag(const std::map<int, std::string>& names, const std::string& key) {
    for (const auto& [tag, name] : names)
        if (name == key) return tag;
    char* end = nullptr;
    const long v = std::strtol(key.c_str(), &end, 10);
    if (end == key.c_str() || *end != '\0' || v < INT_MIN || v > INT_MAX) return std::nullopt;
    return static_cast<int>(v);
}

double units_to_metres(const std::string& units) { return units == "cm" ? 0.01 : units == "mm" ? 0.001 : 1.0; }

void regions_from_cell_data(MeshData& mesh, const std::string& name) {
    const MeshData::CellArray* found = nullptr;
    if (!name.empty()) {
        for (const auto& a : mesh.cell_data)
            if (a.name == name) found = &a;
    } else {
        for (const char* candidate : kRegionArrayNames)
            for (const auto& a : mesh.cell_data)
                if (!found && a.name == candidate) found = &a;
    }
    if (!found) {
        if (name.empty()) return;
        std::string have;
        for (const auto& a : mesh.cell_data) have += fmt::format("{}\"{}\"", have.empty() ? "" : ", ", a.name);
        throw InputError(mesh.source, "mesh.region_array",
                         fmt::format("the file has no cell-data array \"{}\" (it has {})", name, have.empty() ? "none" : have));
    }
    if (found->components != 1 || found->values.size() != mesh.cells.size())
        throw InputError(mesh.source, "mesh.region_array", fmt::format("cell-data array \"{}\" has {} components, not 1", found->name, found->components));
    std::vector<int> region(mesh.cells.size());
    for (size_t e = 0; e < region.size(); ++e) {
        const double v = found->values[e];
        if (v != std::floor(v) || std::abs(v) > 1e9)
            throw InputError(mesh.source, "mesh.region_array",
                             fmt::format("cell-data array \"{}\" holds {:.6g} at {}: regions are integers", found->name, v, mesh.cell_name(e)));
        region[e] = static_cast<int>(v);
    }
    mesh.cell_region = std::move(region);
}


long long reorient_cells(MeshData& mesh) {
    long long flipped = 0;
    const int n = static_cast<int>(mesh.points.size());
    for (auto& c : mesh.cells) {
        bool valid = true;
        for (int a = 0; a < mesh.nodes_per_cell(); ++a) valid = valid && c[a] >= 0 && c[a] < n;
        if (!valid || !(signed_cell_measure(mesh, c) < 0.0)) continue;  // validate_mesh names bad indices
        std::swap(c[mesh.nodes_per_cell() - 2], c[mesh.nodes_per_cell() - 1]);
        ++flipped;
    }
    if (flipped)
        mesh.notes.push_back(fmt::format("{} inverted {} reoriented (mesh.reorient)", flipped,
                                         mesh.dim == 3 ? "tetrahedra" : "triangles"));
    return flipped;
}

long long drop_unused_nodes(MeshData& mesh) {
    const int n = static_cast<int>(mesh.points.size());
    std::vector<int> remap(mesh.points.size(), -1);
    int used = 0;
    for (const auto& c : mesh.cells)
        for (int a = 0; a < mesh.nodes_per_cell(); ++a)
            if (c[a] >= 0 && c[a] < n && remap[c[a]] < 0) remap[c[a]] = 0;
    for (int& r : remap)
        if (r == 0) r = used++;
    const long long dropped = n - used;
    if (dropped == 0) return 0;
    std::vector<Eigen::Vector3d> points(used);
    std::vector<long long> ids(mesh.point_id.empty() ? 0 : used);
    std::vector<int> file_index(used);
    if (mesh.file_points < 0) mesh.file_points = n;
    for (int i = 0; i < n; ++i)
        if (remap[i] >= 0) {
            points[remap[i]] = mesh.points[i];
            file_index[remap[i]] = mesh.file_index.empty() ? i : mesh.file_index[i];
            if (!ids.empty()) ids[remap[i]] = mesh.point_id[i];
        }
    mesh.file_index = std::move(file_index);
    for (auto& c : mesh.cells)
        for (int a = 0; a < mesh.nodes_per_cell(); ++a)
            if (c[a] >= 0 && c[a] < n) c[a] = remap[c[a]];
    mesh.points = std::move(points);
    mesh.point_id = std::move(ids);
    mesh.notes.push_back(fmt::format("{} node{} no {} uses dropped", dropped, dropped == 1 ? "" : "s",
                                     mesh.dim == 3 ? "tetrahedron" : "triangle"));
    return dropped;
}

}  // namespace xcut
