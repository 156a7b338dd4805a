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

/// HRZ lumped mass share of a corner and of a mid-edge node [-] (of rho V; Hinton, Rock & Zienkiewicz
/// 1976, systems/kernels/quadratic_tet.h): the consistent mass's diagonal scaled to the element's
/// mass. Tetrahedron: 1/36 and 4/27. Triangle: its diagonal is A/30 at a corner and 8A/45 at a
/// mid-edge node (their sum 19A/30), so 1/19 and 16/57.
inline constexpr double kTet10CornerMass = 1.0 / 36.0, kTet10EdgeMass = 4.0 / 27.0;
inline constexpr double kTri6CornerMass = 1.0 / 19.0, kTri6EdgeMass = 16.0 / 57.0;

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

/// The local nodes a 6-node triangle uses of the 10 (corners 0-2, mid-edge nodes of kTet10Edges'
/// first three edges); the others stand for the absent fourth corner and its edges.
inline constexpr int kTri6Locals[6] = {0, 1, 2, 4, 5, 6};

struct QuadraticElements {
    /// 2D: the elements are 6-node triangles (VTK cell type 22), kept as 10-node tetrahedra without
    /// their fourth corner (systems/kernels/quadratic_tet.h, tri3_gradients): their nodes 3, 7, 8 and
    /// 9 repeat node 0 and 4, take no part in the incidence and have zero shape functions.
    bool planar = false;
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
    /// Nodes an element uses (6 or 10), the local index of the k-th of them, its edges (kTet10Edges'
    /// first 3 or all 6).
    int node_count() const { return planar ? 6 : 10; }
    int local(int k) const { return planar ? kTri6Locals[k] : k; }
    int edge_count() const { return planar ? 3 : 6; }
};

}  // namespace xcut
