#pragma once
// Quadratic tetrahedra (10 nodes): the mesh elements of a material with "element": "quadratic"
// (systems/kernels/quadratic_tet.h). Each keeps its corner element in Elements, which the surfaces,
// the contacts and the output go on using; the linear element's stiffness is off for it (its Lamé
// parameters are taken as zero, systems/force_system.h) and the one here stands in. The mid-edge
// nodes are mesh nodes (index < World::mesh_nodes) that no linear element touches, made once at
// load (engine/quadratic_setup.h) and shared by the elements around an edge.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "components/elements.h"

namespace xcut {

/// Local corner pairs of the mid-edge nodes 4..9 (VTK order, cell type 24).
inline constexpr int kTet10Edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};

/// A quadrature rule over one side of a cut quadratic element (systems/kernels/tet10_side_rule.h):
/// points as the parent's barycentric coordinates, weights as fractions of its rest volume.
struct TetSideRule {
    static constexpr int kMaxPoints = 12;
    int count = 0;
    std::array<Eigen::Vector4d, kMaxPoints> L;  ///< barycentric coordinates in the parent [-]
    std::array<double, kMaxPoints> weight{};    ///< fractions of the parent's rest volume [-]
};

struct QuadraticElements {
    std::vector<int> element;                  ///< its corner element in Elements
    std::vector<std::array<int, 10>> nodes;    ///< VTK order: corners, then edges (01 12 02 03 13 23)
    /// per element in Elements (a cut element's virtual ones too): its index here, -1 if linear
    std::vector<int> of_element;
    /// Node -> quadratic element incidence (CSR; entry: element * 16 + local node 0..9), so each
    /// node's terms are summed in a fixed order on any thread count.
    Incidence incidence;
    std::vector<std::array<int, 2>> edge_of_node;  ///< per mid-edge node (index - first_edge_node): its corners
    int first_edge_node = 0;                   ///< the mid-edge nodes are [first_edge_node, World::mesh_nodes)
    /// Per element: its rule in side_rules when it is one side of a cut element, integrated over that
    /// side alone (its weight in Elements is then not applied: the rule's weights are the side's);
    /// -1 (or no entry) for the whole element, Keast's 4 points.
    std::vector<int> side_rule;
    std::vector<TetSideRule> side_rules;
    /// Per side rule: its side's HRZ masses of the 10 nodes as fractions of rho V (the parent's rest
    /// volume), made at the split (tet10_side_masses).
    std::vector<std::array<double, 10>> side_masses;

    int count() const { return static_cast<int>(element.size()); }
};

}  // namespace xcut
