#pragma once
// State of the snapping-and-subdivision cutter (the baseline the paper compares XFEM against,
// §4.1-4.2; systems/cut/snap_cut_system.h). The mesh elements [0, mesh_elements) keep their node ids,
// so the CutSystem decides on the same mesh for both cutters; a mesh element the cutter touched
// gets weight 0 and is carried by its *pieces*, force elements appended after the mesh elements.
// New DOF nodes (edge points, the copies made when a node is duplicated across a cut, and the
// mid-edge nodes of quadratic pieces' new edges) are appended after the mesh nodes.
//
// Each piece remembers its nodes as *roots* (mesh nodes and edge points, before duplication) and
// its side of the cut; which copy of a root it uses is looked up per (root, mesh element, side).
#include <array>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace xcut {

struct SnapMesh {
    bool enabled = false;            ///< the scene's cutter is "snap" (else XFEM)
    /// A crossing closer to a node than this fraction of the edge's length moves the node onto the
    /// cut instead of adding a point [-]. Default 0.1: SOFA's incision along a path (the snapping
    /// and subdivision the paper compares with, TriangleSetTopologyAlgorithms / TopologicalChange
    /// Manager) uses a snapping value of 20 %, turned into 0.20 / 2 = 0.1 of the edge's barycentric
    /// coordinate; border points are not snapped (snapping border value 0), as here.
    double threshold = 0.1;
    int visual_subdivisions = -1;     ///< rebuild the visual surface with this many subdivisions (-1: none)
    int collision_subdivisions = -1;  ///< the same for the collision surface

    // Per mesh node.
    std::vector<uint8_t> snapped;        ///< moved onto a cut surface (a root of the cut surface)
    std::vector<uint8_t> boundary_node;  ///< on the body's boundary: moves only along boundary edges
    std::unordered_set<uint64_t> boundary_edges;  ///< mesh edges on the boundary (sorted node pair)

    // Per mesh element.
    std::vector<uint8_t> split;                 ///< its cut has been applied
    std::vector<std::array<int8_t, 4>> level;   ///< per local node: side +1 / -1, 0 on the cut (snapped)
    std::vector<std::vector<int>> pieces;       ///< force elements carrying it; empty: untouched, itself

    // Per force element beyond the mesh elements (index - mesh_elements).
    std::vector<int> piece_parent;                  ///< mesh element it is a piece of
    std::vector<int8_t> piece_side;                 ///< +1 / -1 of a split element, 0 of a whole one
    std::vector<std::array<int, 4>> piece_roots;    ///< its nodes before duplication
    std::vector<uint8_t> piece_live;                ///< 0: a spare slot (weight 0)

    // Edge points and copies.
    std::unordered_map<uint64_t, int> edge_point;   ///< mesh edge (sorted node pair) -> its point's node
    std::vector<std::array<int, 2>> extra_edge;     ///< per node beyond the mesh nodes: edge of a point, {-1,-1} for a copy or a mid-edge node
    std::vector<int> extra_root;                    ///< per node beyond the mesh nodes: the root it copies (itself for a point or a mid-edge node)
    std::map<std::array<int, 3>, int> copy;         ///< (root, mesh element, side) -> DOF node used there
    /// Quadratic elements (systems/cut/snap_quadratic.h): the mid-edge node of the pieces' edge between
    /// two DOF nodes (sorted pair), the mesh's own mid-edge nodes first.
    std::unordered_map<uint64_t, int> mid_node;

    // Figures.
    int snaps = 0;                     ///< nodes moved onto a cut
    int points = 0;                    ///< edge points made
    int copies = 0;                    ///< nodes duplicated
    int mid_nodes = 0;                 ///< mid-edge nodes made for the pieces of quadratic elements
    /// Pieces whose rest shape came out inverted: snaps of two nodes of one element in one step
    /// can turn a sliver over. They keep |V| (a positive mass and a positive semi-definite
    /// stiffness; their current shape is inverted with them, so they exert no spurious force).
    int inverted_pieces = 0;
    int elements_split = 0;            ///< mesh elements whose cut was applied
    std::vector<double> snap_fraction; ///< per snap: distance moved / length of the edge it moved along [-]
    double max_snap_distance = 0.0;    ///< largest distance a node was moved [m]
};

}  // namespace xcut
