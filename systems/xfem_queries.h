#pragma once
// The XFEM queries other systems read the cut through (a seam, like systems/step_term.h): the
// surface code asks where the crack crosses an edge and whether the blade has crossed it; output
// and studies ask a node's enriched displacement. They read the cut components only (CutElements,
// EnrichedDofs); the EnrichmentSystem (systems/cut/enrichment_system.h) is what writes them.
#include <Eigen/LU>
#include <array>
#include <span>

#include "engine/world.h"
#include "systems/kernels/branch_enrichment.h"

namespace xcut {

/// Mesh edge a-b has been crossed by the blade: some cut element holding it has its bit in
/// CutElements::crossed. False for an edge no cut element holds.
bool edge_crossed(const World& world, int a, int b);

/// Where the crack crosses mesh edge a -> b: the parameter from a of the point a cut element holding
/// the edge put on it, or -1 if no cut element crosses it. One crack has one point per edge: an
/// element split later takes this one, and the surface cuts along it.
double crack_edge_param(const World& world, int a, int b);

/// Crack tips (components/crack_tips.h): the lip (+1: the normal's side of tip frame `tip`, -1) a
/// mesh node lies on when it sits on the crack's line behind the tip, from its Heaviside sign; 0
/// elsewhere (atan2 decides). A node's branch-function shift F_l(X_j) is taken on that lip, so
/// every element around it agrees.
int tip_node_lip(const World& world, const Vec2& tip_point, const Vec2& tip_direction, int node);
/// The same for a crack's plane in 3D (2D: z's), behind `point` along -`direction`, its lips on
/// either side of `normal` (each unit).
int crack_node_lip(const World& world, const Vec3& point, const Vec3& direction, const Vec3& normal, int node);

/// The enrichment of zone element z (CrackTips index) at its rest point X with barycentric L over
/// its mesh element's corners: Σ_k L_k Σ_l (F_l(X) - F_l(X_k)) b_kl over the corners its functions
/// belong to, F on lip `lip` of z's tip (0: atan2), b the amplitudes (2 per function) [m]. A point's
/// enriched position is its element's linear interpolation plus this over the zone elements that
/// are its force element (systems/cut/crack_tip_system.h).
Vec3 tip_enrichment(const World& world, const Eigen::VectorXd& amplitudes, int z, const Vec2& X, const Vec3& L, int lip);

/// A straight crack front's enrichment (3D, systems/kernels/front_enrichment.h) of zone element z
/// at its rest point X with barycentric `bary`: Σ_k N_k Σ_l (F_l(X) - F_l(X_k)) b_kl on z's lip
/// (CrackTips::lip; 0: X's side of the crack's plane), or on lip `lip` where it is not 0 (a point on
/// the crack's plane behind the front, shown once per lip: systems/surface/surface_fronts.cpp),
/// b 3 per function, world frame [m]. The displacement the surface, the probes and the volume
/// output add to the linear interpolation.
Vec3 front_enrichment(const World& world, const Eigen::VectorXd& amplitudes, int z, const Vec3& X, const Eigen::Vector4d& bary,
                      int lip = 0);

/// The enriched position at rest point X of force element fe (barycentric L over its corners): its
/// linear interpolation plus tip_enrichment over the zone elements that are fe, on lip `lip` for
/// tip `tip` and each other tip's on the element's own lip (CrackTips::lip; 0: atan2) [m]. What the
/// volume output and the visual surface show inside the tips' elements.
Vec3 tip_field(const World& world, const Eigen::VectorXd& amplitudes, int fe, const Vec2& X, const Vec3& L, int tip, int lip);

/// The rest triangles of a 2D mesh as the crack tips' code takes them (systems/cut/crack_tip_system.cpp,
/// crack_tip_display.cpp, systems/surface/surface_tips.cpp): a mesh element's corners in the plane,
/// and a point's barycentric coordinates in them (by LU: engine/fragment_geometry.h's
/// triangle_barycentric rounds differently, and the tips' recorded runs were made with this one).
namespace tip_triangles {

inline Vec2 xy(const Vec3& v) { return v.head<2>(); }

/// Mesh element e's rest corners in the plane [m].
inline std::array<Vec2, 3> rest_triangle(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {xy(w.nodes.rest[n[0]]), xy(w.nodes.rest[n[1]]), xy(w.nodes.rest[n[2]])};
}

/// The barycentric coordinates of point T in triangle X.
inline Vec3 barycentric(const std::array<Vec2, 3>& X, const Vec2& T) {
    Eigen::Matrix2d D;
    D << X[1] - X[0], X[2] - X[0];
    const Vec2 l = D.partialPivLu().solve(T - X[0]);
    return Vec3(1.0 - l.x() - l.y(), l.x(), l.y());
}

}  // namespace tip_triangles

/// The mesh node that DOF node `node` is (itself) or copies (a phantom's node).
inline int mesh_node(const World& world, int node) {
    return node >= world.mesh_nodes ? world.enriched.node_of_phantom[node - world.mesh_nodes] : node;
}

/// The mesh element force element fe is or stands for: a virtual element's parent, a snapping
/// piece's element (-1: none).
inline int mesh_element_of(const World& w, int fe) {
    if (fe < w.mesh_elements) return fe;
    const size_t k = static_cast<size_t>(fe - w.mesh_elements);
    if (w.snap.enabled) return k < w.snap.piece_parent.size() ? w.snap.piece_parent[k] : -1;
    return k < w.virtual_elements.parent.size() ? w.virtual_elements.parent[k] : -1;
}

/// A nodal field (positions, velocities) at barycentric `b` of force element `element`, linear over
/// its corners (eq. 4, 6): how a surface vertex or a probe point bound to it moves.
inline Vec3 bound_value(const World& w, int element, const Eigen::Vector4d& b, const std::vector<Vec3>& field) {
    const auto& nodes = w.elements.nodes[element];
    Vec3 p = Vec3::Zero();
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) p += b[a] * field[nodes[a]];
    return p;
}
/// Current position of the point at barycentric `b` of force element `element` [m], as
/// update_surface_positions places a surface vertex.
inline Vec3 bound_position(const World& w, int element, const Eigen::Vector4d& b) {
    return bound_value(w, element, b, w.nodes.position);
}

/// Where cut element c's first cut crosses its local edges (3D, kTetEdges order, from the edge's
/// first node; -1 where it does not): its points.
std::array<double, 6> first_edge_params(const World& world, int c);
/// Where line l of cut element c crosses its local edges (3D, as first_edge_params): the cut's own
/// points (CutElements::line_edge_t), or, for an element cut once along the nodes' sides (no
/// lines), its first cut's.
std::array<double, 6> line_edge_params(const World& world, int c, size_t l);
/// Element f's local edge (kTetEdges order; a triangle's: kTriEdges) joining mesh nodes a and b, -1
/// if it has none; `from_a`: whether the edge runs from a.
int local_edge_of(const World& world, int f, int a, int b, bool& from_a);
/// A parameter on element f's local edge k (from its first node, as line_edge_params) measured from
/// node a instead: t, or 1 - t where the edge runs from b; -1 stays -1 (no crossing).
inline double param_from(double t, bool from_a) { return t < 0.0 ? t : from_a ? t : 1.0 - t; }

/// Whether this world cuts an element again (linear elements, the XFEM cutter, no crack tips, and
/// CutState::recut: on by default in 2D, asked for in 3D; in 3D the cuts a scene scripts, in 2D
/// also the scalpels'). Where it does not, a cut that crosses an element along another line keeps
/// the first (CutState::recut_ignored says so).
bool recut_allowed(const World& world);

/// Whether the blades' sweeps are sampled and cut at their turns (kTurnFraction, blade_pose.h): in
/// 3D where elements are not cut again. With recut (and in 2D) the stems and loops take their quads
/// from the threshold alone.
bool cuts_at_turns(const World& world);

/// The virtual elements of cut element c: its two sides, or its fragments once cut again
/// (CutElements::fragments). A view into the cut components: a caller that changes them copies it first.
inline std::span<const int> fragments_of(const World& world, int c) {
    if (!world.cuts.fragments[c].empty()) return world.cuts.fragments[c];
    return world.cuts.virtual_element[c];
}

/// a_j of mesh node j (eq. 6), zero if the node has no phantom.
Vec3 enriched_displacement(const World& world, int node);
Vec3 enriched_velocity(const World& world, int node);

}  // namespace xcut
