#pragma once
// XFEM state (paper §3.1, §3.2, App. A). A cut element keeps its nodes; each of its nodes gains one
// enriched DOF a_j (shifted Heaviside, eq. 9), and the element is carried from then on by two
// *virtual elements* (the alternative mesh, Fig. 3-5), one per side of the cut.
//
// Storage follows the paper's Fig. 4: in place of a_j we store the real position of the vertex of
// the virtual element on the other side of the cut (the "phantom" copy of node j), as an extra DOF
// node appended after the mesh nodes. With H_j the node's side, eq. 6 gives
//   H_j = +1:  p_aj = x_j,          p_bj = x_j - a_j = y_j   ->  a_j = x_j - y_j
//   H_j = -1:  p_aj = x_j + a_j = y_j,  p_bj = x_j           ->  a_j = y_j - x_j
// a linear, invertible change of variables, so forces, stiffness and implicit Euler steps are those
// of eq. 1-5 (tests/systems/test_xfem_element.cpp checks this against the paper's formulas to 1e-12).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "components/nodes.h"

namespace xcut {

/// A cut line through an element (2D): a point on it and its unit normal, toward the side its bit
/// names 1 (rest [m]).
struct CutLine {
    Vec3 origin = Vec3::Zero();
    Vec3 normal = Vec3::Zero();
};

/// Cut lines an element can hold: its first cut and three more (docs/xfem.md, Several cuts per
/// element). A further cut through it is not made, and counted (CutState::recut_ignored).
inline constexpr int kMaxElementLines = 4;

/// Two fragments and a face between them: each fragment by its virtual element (-1 - element for a
/// whole one) and its mask (VirtualElements::mask, 0 whole), then the face's three nodes (sorted;
/// 2D: -1 and the edge's two). A fragment's part of a face follows from these alone: the lines its
/// mask names are never changed once added.
using FaceShareKey = std::array<int, 7>;
inline constexpr size_t kFaceShareMemoEntries = size_t{1} << 16;  ///< the memo's bound (a few MB)
struct FaceShareHash {
    size_t operator()(const FaceShareKey& k) const {
        size_t h = 0;
        for (int v : k) h = h * 0x9E3779B97F4A7C15ull + static_cast<size_t>(static_cast<unsigned>(v));
        return h;
    }
};

/// One entry per cut mesh element.
struct CutElements {
    std::vector<int> element;                    ///< the mesh element that was cut
    std::vector<double> fraction_above;          ///< exact V_a / V of the rest shape [-]
    std::vector<std::array<Vec3, 4>> points;     ///< edge intersection points, rest configuration [m]
    std::vector<std::array<int8_t, 4>> point_edge;  ///< local edge (0..5; 2D 0..2) of each point, -1 unused
    std::vector<std::array<int, 2>> virtual_element;  ///< [above, below]: indices into VirtualElements
    /// Local edges (bit k: edge k) the blade has crossed. A split edge whose bit is clear lies on the
    /// cut's extension ahead of the blade (a progressive front's tip element): the crack-front rule
    /// holds its nodes. Every other cut has all bits set.
    std::vector<uint8_t> crossed;
    std::vector<double> entered_time;            ///< simulated time the blade first crossed it [s]
    std::vector<double> entered_wall;            ///< wall time of that crossing [s]
    std::vector<uint8_t> opened;                 ///< a virtual vertex is a phantom: the wound can open here
    std::vector<int> tool;                       ///< the bladed tool whose cut split it, -1 a scripted cut

    /// Per cut element, once it opened: time from the blade's first crossing to the opening
    /// (simulated [s], wall [s]). The crossing delay a user sees.
    std::vector<double> open_delay_sim, open_delay_wall;
    /// Split mesh edges (node pairs) whose crossing came after their element's split, in order: the
    /// surface re-makes the pieces around them (SurfaceMesh::crossings_mapped).
    std::vector<std::array<int, 2>> crossed_log;

    std::vector<int> cut_of_element;             ///< per mesh element: index here, -1 if uncut

    /// Several cuts per element (2D). Per cut element: its cut lines, the first through `points`
    /// oriented toward its side +1, then one per further cut; empty while it is cut once along the
    /// nodes' sides (EnrichedDofs::sign). An element with lines is divided into fragments, the parts
    /// of it on one side of each line (VirtualElements::mask), each a virtual element.
    std::vector<std::vector<CutLine>> lines;
    /// 3D, per cut element with lines, per line: where it crosses each local edge (kTetEdges order;
    /// parameter from the edge's first node, -1 where it does not), the cut's own points: two
    /// elements sharing a face see one trace of a cut there, though the planes fitted through
    /// their points (on tissue that had moved) differ by micrometres (systems/cut/node_copies.cpp).
    std::vector<std::vector<std::array<double, 6>>> line_edge_t;
    /// Per cut element with lines: its fragments' virtual elements (virtual_element's two first).
    std::vector<std::vector<int>> fragments;
    /// Cut elements cut again, in order (one entry per further cut): the surfaces re-make them.
    std::vector<int> recut_log;

    /// Node copies' memo of which neighbouring fragments hold one material across their common face
    /// (systems/cut/node_copies.cpp, SharedFaces): derived data, the same answers recomputed would
    /// give, kept between steps and emptied when it passes FaceShareKey's bound.
    std::unordered_map<FaceShareKey, uint8_t, FaceShareHash> face_shares;
    /// The element and node counts up to which the arrays' reserved room was last asked to be
    /// made resident (fault_room_ahead, systems/cut/enrichment_system.h): asked again only when a
    /// split comes within half the stretch of it.
    size_t room_elements = 0, room_nodes = 0;

    int count() const { return static_cast<int>(element.size()); }
};

/// The alternative mesh: two per cut element. Each is also a force element (in Elements, after the
/// mesh elements) whose vertices are real or phantom DOF nodes, with weight V_s/V and its own
/// rotation R_s (eq. 2, 3).
struct VirtualElements {
    std::vector<int> parent;       ///< mesh element it comes from
    std::vector<int8_t> side;      ///< +1 above (H > 0), -1 below
    std::vector<int> element;      ///< its force element index in Elements
    /// Its side of each of its cut element's lines that bound it (CutElements::lines; bit k: line
    /// k's normal side, bit 16 + k: line k bounds it; engine/fragment_geometry.h); bit 16 and bit 0
    /// (side > 0) while the element is cut once.
    std::vector<uint32_t> mask;

    int count() const { return static_cast<int>(parent.size()); }
};

/// Enriched DOFs, per mesh node.
struct EnrichedDofs {
    std::vector<int8_t> sign;          ///< H_j: +1 above, -1 below, 0 not yet met by a cut
    std::vector<uint8_t> enriched;     ///< node belongs to a cut element
    /// Crack-front rule (§3.5): some part of a cut element on the other side from the node still
    /// uses the real node there (a_j = 0 for it), as material connectivity joins them
    std::vector<uint8_t> front_fixed;
    /// The node's first phantom (a DOF node holding a part of the material across a cut), -1 if
    /// none. A node has one copy per class of material connectivity around it (docs/xfem.md,
    /// Node copies): the real node and as many phantoms as there are other classes; the virtual
    /// elements name them, node_of_phantom maps each back.
    std::vector<int> phantom;
    /// The unit normal of the cut that fixed H_j (rest configuration), pointing to the side H = +1;
    /// zero while H_j = 0 (a crack tip's lips, systems/cut/crack_tip_system.cpp).
    std::vector<Vec3> sign_normal;
    std::vector<int> node_of_phantom;  ///< per phantom (index - mesh_nodes): its mesh node
    /// per phantom: the DOF node whose state it started from (its mesh node, or an earlier phantom
    /// of that node when a cut divides the material that phantom held)
    std::vector<int> phantom_from;

    int count() const { return static_cast<int>(node_of_phantom.size()); }
};

/// A split requested by a cutter: an element and the cut surface through it, as node levels
/// (signed distances to the cut surface, current configuration [m]) and edge crossing points.
/// For an element already cut (a progressive front's tip element), only `crossed` is read: the
/// edges the blade has crossed since.
struct CutEvent {
    int element = -1;
    uint8_t crossed = 0xFF;               ///< local edges the blade crossed (all: a full cut)
    double entered_time = -1.0;           ///< first crossing [s] (simulated; < 0: now)
    double entered_wall = -1.0;           ///< first crossing [s] (wall; < 0: now)
    std::array<double, 4> level{};        ///< per local node; sign gives H_j unless already set
    std::array<double, 6> edge_t{};       ///< per local edge: crossing parameter in [0, 1] from its first node
    std::array<uint8_t, 6> edge_has_t{};  ///< edge_t is given (else taken from the levels)
    int tool = -1;                        ///< the bladed tool whose blade made it, -1 a scripted cut
    /// A further cut through an element already cut: the line (plane) where its levels change sign
    /// divides the element's fragments it crosses from side to side within `extent`
    /// (systems/cut/recut.h).
    bool again = false;
    bool bounded = false;                 ///< the cut ends inside the element: only `extent` is cut
    /// 2D: rest points on the line between which it cuts [m]. 3D (a T's stem, systems/cut/stem_3d.h):
    /// a rest point on the blade's edge where it began [m] and the unit normal of the boundary
    /// through that edge, toward the part of the plane it cuts.
    std::array<Vec3, 2> extent{Vec3::Zero(), Vec3::Zero()};
};

/// Local edges of a tetrahedron / triangle as node pairs.
inline constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
inline constexpr int kTriEdges[3][2] = {{0, 1}, {1, 2}, {2, 0}};

}  // namespace xcut
