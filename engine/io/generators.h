#pragma once
// Built-in structured meshes, parameterized by element size, for scenes and benchmarks.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "engine/mesh_data.h"

namespace xcut {

struct GridSpec {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< min corner [m]
    Eigen::Vector3d size = Eigen::Vector3d::Ones();    ///< extent [m] (2D: z ignored)
    Eigen::Vector3i cells = Eigen::Vector3i::Ones();   ///< cells per axis
    double jitter = 0.0;      ///< interior nodes moved by up to jitter * cell size (irregular meshes)
    uint64_t seed = 1;        ///< jitter's random seed (reproducible)
    double bend_radius = 0.0; ///< > 0: wrap the box's y extent around a cylinder along x [m]
};

/// Box of hexahedral cells, each split into 6 tetrahedra around its main diagonal (Kuhn): conforming
/// because every cell is split the same way. Tet count = 6 * cells.prod().
MeshData generate_box(const GridSpec& spec);
/// The same Kuhn split on a tensor-product grid: node coordinates along x, y and z (each increasing,
/// at least two), so a chosen plane can be a grid plane (a conforming crack, tools/studies/crack_reference.h).
MeshData generate_box_on_lines(const std::array<std::vector<double>, 3>& lines);
/// Wraps a box around the x axis: the mid-line y = origin.y + size.y / 2 becomes the crest at
/// y = 0; the bottom face z = origin.z lies on the cylinder of radius `radius` whose top is z = 0,
/// and z above it stays the distance from that cylinder (a skin layer of constant thickness).
void bend_around_x(MeshData& mesh, const GridSpec& spec);
/// Rectangle in the xy plane, each cell split into 2 triangles. Triangle count = 2 * cx * cy.
MeshData generate_plate(const GridSpec& spec);
/// Cells per axis so that the cell edge is close to `element_size` (at least one cell per axis).
Eigen::Vector3i cells_for_size(const Eigen::Vector3d& size, double element_size);

}  // namespace xcut
