#include <Eigen/Dense>
#include <fmt/format.h>

#include "engine/error.h"
#include "engine/mesh_data.h"

namespace xcut {

std::string MeshData::point_name(size_t i) const {
    return i < point_id.size() ? fmt::format("node {}", point_id[i]) : fmt::format("points[{}]", i);
}

std::string MeshData::cell_name(size_t e) const {
    return e < cell_id.size() ? fmt::format("element {}", cell_id[e]) : fmt::format("cells[{}]", e);
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
            throw InputError(src, mesh.point_name(i), "coordinate is NaN or infinite");
    const int npe = mesh.nodes_per_cell();
    const int n = static_cast<int>(mesh.points.size());
    for (size_t e = 0; e < mesh.cells.size(); ++e) {
        const auto& c = mesh.cells[e];
        const std::string field = mesh.cell_name(e);
        for (int a = 0; a < npe; ++a) {
            if (c[a] < 0 || c[a] >= n)
                throw InputError(src, field, fmt::format("node index {} is out of range (the mesh has {} nodes)", c[a], n));
            for (int b = 0; b < a; ++b)
                if (c[a] == c[b]) throw InputError(src, field, fmt::format("{} appears twice", mesh.point_name(c[a])));
        }
        double longest = 0.0;
        for (int a = 0; a < npe; ++a)
            for (int b = a + 1; b < npe; ++b) longest = std::max(longest, (mesh.points[c[a]] - mesh.points[c[b]]).norm());
        if (mesh.dim == 2 && (mesh.points[c[0]].z() != 0.0 || mesh.points[c[1]].z() != 0.0 || mesh.points[c[2]].z() != 0.0))
            throw InputError(src, field, "2D meshes lie in the plane z = 0");
        const double measure = signed_cell_measure(mesh, c);
        const double tol = rel_tol * std::pow(longest, mesh.dim);
        const char* unit = mesh.dim == 3 ? "m^3" : "m^2";
        if (measure < -tol)
            throw InputError(src, field, fmt::format("is inverted (signed {} {:.3g} {}): node order must be positive (mesh.reorient: true flips such cells)",
                                                     mesh.dim == 3 ? "volume" : "area", measure, unit));
        if (!(measure > tol))
            throw InputError(src, field, fmt::format("is degenerate ({} {:.3g} {})", mesh.dim == 3 ? "volume" : "area",
                                                     measure, unit));
    }
}

}  // namespace xcut
