#pragma once
// A triangle surface carried by the simulation mesh (paper §3.2, §3.4): the visual surface and,
// separately, the collision surface. Each vertex is bound barycentrically to one element, a mesh
// element while that is whole, afterwards the virtual element of the vertex's side of the cut (the
// alternative mesh, Fig. 5). A reverse index from mesh elements to their bound vertices lets a cut
// re-bind only the vertices of the elements it split.
//
// The *base* triangles are the body's skin as built (never changed); the output `triangles` are
// what each mesh element currently shows: its base triangles as they are, split along a cut, or
// split at the crack-front points on its edges, plus the internal cut faces of a cut element.
// `pieces_of` lists each element's output triangles, so a cut regenerates only the pieces of the
// elements it touched.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct SurfaceMesh {
    std::vector<Vec3> position;              ///< current positions [m], from the bindings
    std::vector<int> element;                ///< binding: force element (mesh or virtual)
    std::vector<Eigen::Vector4d> bary;       ///< barycentric coordinates in that element's rest shape
    std::vector<int8_t> side;                ///< side of the cut the vertex is on (H): 0 until a cut reaches it
    std::vector<std::array<int, 3>> triangles;  ///< outward-oriented
    std::vector<int> triangle_owner;         ///< mesh element whose piece the triangle is
    std::vector<uint8_t> cut_face;           ///< 1: a triangle of the internal cut surface (§3.4)
    std::vector<std::vector<int>> bound_to;  ///< per mesh element: the vertices bound to it
    std::vector<std::array<int, 3>> base_triangles;  ///< the skin as built, outward
    std::vector<std::vector<int>> base_of;   ///< per mesh element: its base triangles
    std::vector<std::vector<int>> pieces_of; ///< per mesh element: its output triangles
    std::vector<int> node_vertex;            ///< per mesh node: its base vertex, -1 if none
    /// Base vertices by quantized rest position (surface_place): a cut point landing exactly on one
    /// (a crossing at a subdivision midpoint) is that vertex on its own side, never a second copy.
    std::map<std::array<int64_t, 3>, int> base_vertex_at;
    /// Points made by cuts, made once and reused by every element and triangle that meets them (the
    /// paper's "existing or future points"). Key: {kind, a, b, c}: a point on a mesh edge is
    /// {side, node, node, 0} (side 0 while some whole element still holds the edge, or, on a
    /// progressive front, the blade has not crossed it yet: the crack front, where both lips are
    /// one vertex); any other point {side + 4, quantized rest position}.
    std::map<std::array<int64_t, 4>, int> cut_point;
    /// Front points split since the surface was last made: {vertex, node a, node b} (a == b for a
    /// node). The pieces still using such a vertex are made again (systems/surface/surface_cut.cpp).
    std::vector<std::array<int, 3>> opened;
    int cuts_mapped = 0;                     ///< cut elements already mapped (CutElements index)
    int crossings_mapped = 0;                ///< CutElements::crossed_log entries already mapped
    int recuts_mapped = 0;                   ///< CutElements::recut_log entries already mapped
    /// Every point a cut made, by quantized rest position: an element cut more than once (2D) takes
    /// the one there whose material is its own (systems/surface/surface_fragments.cpp).
    std::multimap<std::array<int64_t, 3>, int> point_at;
    int last_rebound = 0;                    ///< vertices re-bound by the last mapping update
    /// The crack tips' opening shown inside their elements (systems/surface/surface_tips.h) is laid
    /// over the surface and taken off before it is cut or shown again: while it lies (tip_first_vertex
    /// >= 0) the triangles are the tip_saved_* ones without the tips' elements' pieces, plus a fan
    /// from each tip, and the vertices from tip_first_vertex on are its own.
    int tip_first_vertex = -1;
    /// per tip opened: its vertex, and where the crack enters its element on the + lip and the - lip
    std::vector<std::array<int, 3>> tip_vertices;
    std::vector<std::array<int, 3>> tip_saved_triangles;
    std::vector<int> tip_saved_owner;
    std::vector<uint8_t> tip_saved_cut_face;
    /// 3D fronts (systems/surface/surface_fronts.cpp): elements slit at the last overlay, and the
    /// overlays since the surface was built at which a front was not slit, its slit leaving the
    /// surface open (the front's field still places every vertex).
    int front_slit_elements = 0, front_slits_refused = 0;
    /// Where wounds touch along a line or coincide, laid over the surface after each cut and taken
    /// off before the next (systems/surface/surface_manifold.h): the first copy of a vertex (-1:
    /// nothing laid), the vertex each copy was made of, and the triangles as the cut made them.
    int manifold_first_vertex = -1;
    std::vector<int> manifold_source;
    std::vector<std::array<int, 3>> manifold_saved_triangles;
    std::vector<int> manifold_saved_owner;
    std::vector<uint8_t> manifold_saved_cut_face;

    /// Its defects as drawn after the last step that cut it (systems/surface/surface_check.h: edges
    /// open or pinched, triangles without area), and the simulated time they were first seen [s]
    /// (-1: none now).
    int open_edges = 0, pinched_edges = 0, zero_area = 0;
    double defects_since = -1.0;

    int vertex_count() const { return static_cast<int>(position.size()); }
    /// The vertex v was made of: itself, unless it is a copy where wounds touch (manifold_source).
    int source_vertex(int v) const {
        return manifold_first_vertex >= 0 && v >= manifold_first_vertex ? manifold_source[v - manifold_first_vertex] : v;
    }
};

}  // namespace xcut
