#include "engine/io/generators.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <random>

namespace xcut {
namespace {

/// Moves interior grid nodes by a seeded uniform offset; boundary nodes keep the exact box shape.
void jitter_interior(MeshData& mesh, const GridSpec& spec, int dims) {
    if (spec.jitter <= 0.0) return;
    std::mt19937_64 rng(spec.seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Eigen::Vector3d h = spec.size.cwiseQuotient(spec.cells.cast<double>());
    const double eps = 1e-9 * h.minCoeff();
    for (auto& p : mesh.points) {
        Eigen::Vector3d offset = Eigen::Vector3d::Zero();
        bool interior = true;
        for (int k = 0; k < dims; ++k) {
            offset[k] = unit(rng) * spec.jitter * h[k];
            interior = interior && p[k] > spec.origin[k] + eps && p[k] < spec.origin[k] + spec.size[k] - eps;
        }
        if (interior) p += offset;
    }
}

}  // namespace

Eigen::Vector3i cells_for_size(const Eigen::Vector3d& size, double element_size) {
    Eigen::Vector3i c;
    // Clamped in double before the cast, so a tiny element size cannot overflow an int: the scene's
    // element-count limit then refuses the result.
    for (int k = 0; k < 3; ++k) c[k] = static_cast<int>(std::clamp(std::round(size[k] / element_size), 1.0, 1e8));
    return c;
}

MeshData generate_box_on_lines(const std::array<std::vector<double>, 3>& lines) {
    MeshData mesh;
    mesh.dim = 3;
    mesh.source = "generator box";
    const Eigen::Vector3i c(static_cast<int>(lines[0].size()) - 1, static_cast<int>(lines[1].size()) - 1,
                            static_cast<int>(lines[2].size()) - 1);
    auto id = [&](int i, int j, int k) { return (k * (c.y() + 1) + j) * (c.x() + 1) + i; };
    for (int k = 0; k <= c.z(); ++k)
        for (int j = 0; j <= c.y(); ++j)
            for (int i = 0; i <= c.x(); ++i) mesh.points.emplace_back(lines[0][i], lines[1][j], lines[2][k]);
    // The six monotone lattice paths from corner (0,0,0) to (1,1,1), one tet each.
    static const int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int k = 0; k < c.z(); ++k)
        for (int j = 0; j < c.y(); ++j)
            for (int i = 0; i < c.x(); ++i)
                for (const auto& perm : kPerm) {
                    Eigen::Vector3i at(i, j, k);
                    std::array<int, 4> tet;
                    tet[0] = id(at.x(), at.y(), at.z());
                    for (int s = 0; s < 3; ++s) {
                        at[perm[s]] += 1;
                        tet[s + 1] = id(at.x(), at.y(), at.z());
                    }
                    mesh.cells.push_back(tet);
                }
    for (auto& t : mesh.cells) {
        Eigen::Matrix3d D;
        for (int s = 0; s < 3; ++s) D.col(s) = mesh.points[t[s + 1]] - mesh.points[t[0]];
        if (D.determinant() < 0) std::swap(t[2], t[3]);
    }
    return mesh;
}

MeshData generate_box(const GridSpec& spec) {
    std::array<std::vector<double>, 3> lines;
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i <= spec.cells[a]; ++i)
            lines[a].push_back(spec.origin[a] + spec.size[a] * (double(i) / spec.cells[a]));
    MeshData mesh = generate_box_on_lines(lines);
    jitter_interior(mesh, spec, 3);
    if (spec.bend_radius > 0.0) bend_around_x(mesh, spec);
    return mesh;
}

void bend_around_x(MeshData& mesh, const GridSpec& spec) {
    const double R = spec.bend_radius, yc = spec.origin.y() + 0.5 * spec.size.y();
    for (auto& p : mesh.points) {
        const double theta = (p.y() - yc) / R, r = R + (p.z() - spec.origin.z());
        p.y() = r * std::sin(theta);
        p.z() = r * std::cos(theta) - R;
    }
}

MeshData generate_plate(const GridSpec& spec) {
    MeshData mesh;
    mesh.dim = 2;
    mesh.source = "generator plate";
    const int cx = spec.cells.x(), cy = spec.cells.y();
    auto id = [&](int i, int j) { return j * (cx + 1) + i; };
    for (int j = 0; j <= cy; ++j)
        for (int i = 0; i <= cx; ++i)
            mesh.points.emplace_back(spec.origin.x() + spec.size.x() * i / cx,
                                     spec.origin.y() + spec.size.y() * j / cy, 0.0);
    for (int j = 0; j < cy; ++j)
        for (int i = 0; i < cx; ++i) {
            mesh.cells.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), -1});
            mesh.cells.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1), -1});
        }
    jitter_interior(mesh, spec, 2);
    return mesh;
}

}  // namespace xcut
