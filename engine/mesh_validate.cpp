#include <Eigen/Dense>
#include <fmt/format.h>

#include <algorithm>

#include "engine/error.h"
#include "engine/mesh_data.h"

namespace xcut {

namespace {

/// "node 44", or where several of the file's nodes carry that id, which one it is too.
std::string named(const char* kind, const std::vector<long long>& ids, size_t i, const char* array) {
    if (i >= ids.size()) return fmt::format("{}[{}]", array, i);
    const auto same = std::count(ids.begin(), ids.end(), ids[i]);
    if (same == 1) return fmt::format("{} {}", kind, ids[i]);
    const auto nth = std::count(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(i), ids[i]) + 1;
    return fmt::format("{} {} (the file gives {} {}s that id: this is number {} of them, {}[{}] in reading order)",
                       kind, ids[i], same, kind, nth, array, i);
}

}  // namespace

std::string MeshData::point_name(size_t i) const { return named("node", point_id, i, "points"); }

std::string MeshData::cell_name(size_t e) const { return named("element", cell_id, e, "cells"); }

void validate_cell_indices(const MeshData& mesh) {
    const int npe = mesh.nodes_per_cell();
    const long long n = static_cast<long long>(mesh.points.size());
    for (size_t e = 0; e < mesh.cells.size(); ++e)
        for (int a = 0; a < npe; ++a)
            if (mesh.cells[e][a] < 0 || mesh.cells[e][a] >= n)
                throw InputError(mesh.source, mesh.cell_name(e),
                                 fmt::format("node index {} is out of range (the file has {} nodes, indices 0 to {})",
                                             mesh.cells[e][a], n, n - 1));
}

double signed_cell_measure(const MeshData& mesh, const std::array<int, 4>& c) {
    const Eigen::Vector3d u = mesh.points[c[1]] - mesh.points[c[0]], v = mesh.points[c[2]] - mesh.points[c[0]];
    if (mesh.dim == 2) return 0.5 * (u.x() * v.y() - u.y() * v.x());
    Eigen::Matrix3d D;
    D << u, v, mesh.points[c[3]] - mesh.points[c[0]];
    return D.determinant() / 6.0;
}

void validate_mesh(const MeshData& mesh, double rel_tol) {
    const std::string& src = mesh.source;
    if (mesh.dim != 2 && mesh.dim != 3) throw InputError(src, "dimension", fmt::format("must be 2 or 3, not {}", mesh.dim));
    if (mesh.points.empty()) throw InputError(src, "points", "the mesh has no nodes");
    if (mesh.cells.empty()) throw InputError(src, "cells", "the mesh has no elements");
    for (size_t i = 0; i < mesh.points.size(); ++i)
        if (!mesh.points[i].allFinite())
            throw InputError(mesh.points_source.empty() ? src : mesh.points_source, mesh.point_name(i),
                             "coordinate is NaN or infinite");
    validate_cell_indices(mesh);
    const int npe = mesh.nodes_per_cell();
    for (size_t e = 0; e < mesh.cells.size(); ++e) {
        const auto& c = mesh.cells[e];
        for (int a = 0; a < npe; ++a)
            for (int b = 0; b < a; ++b)
                if (c[a] == c[b])
                    throw InputError(src, mesh.cell_name(e), fmt::format("{} appears twice", mesh.point_name(c[a])));
        double longest = 0.0;
        for (int a = 0; a < npe; ++a)
            for (int b = a + 1; b < npe; ++b) longest = std::max(longest, (mesh.points[c[a]] - mesh.points[c[b]]).norm());
        if (mesh.dim == 2 && (mesh.points[c[0]].z() != 0.0 || mesh.points[c[1]].z() != 0.0 || mesh.points[c[2]].z() != 0.0))
            throw InputError(src, mesh.cell_name(e), "2D meshes lie in the plane z = 0");
        const double measure = signed_cell_measure(mesh, c);
        const double tol = rel_tol * std::pow(longest, mesh.dim);
        const char* unit = mesh.dim == 3 ? "m^3" : "m^2";
        if (measure < -tol)
            throw InputError(src, mesh.cell_name(e), fmt::format("is inverted (signed {} {:.3g} {}): node order must be positive (mesh.reorient: true flips such cells)",
                                                     mesh.dim == 3 ? "volume" : "area", measure, unit));
        if (!(measure > tol))
            throw InputError(src, mesh.cell_name(e), fmt::format("is degenerate ({} {:.3g} {})", mesh.dim == 3 ? "volume" : "area",
                                                     measure, unit));
    }
}

}  // namespace xcut
