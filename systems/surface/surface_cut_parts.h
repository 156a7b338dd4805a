#pragma once
// The parts of the surface cut (systems/surface/surface_cut.h) shared by its files:
//  - surface_points.cpp: the mesh around a cut element, and the surface's points bound to a side;
//  - surface_rim.cpp: the cut's plane and trace in an element, and its rim ordered around the cut;
//  - surface_cut_faces.cpp: the cut-face polygons that close the wound;
//  - surface_cut.cpp: the skin subdivided along the cut, and the regeneration of an element's pieces;
//  - surface_tips.cpp: the crack tips' opening laid over the surface;
//  - surface_fronts.cpp: the surface slit inside the elements a 3D front runs through;
//  - surface_fragments.cpp: the pieces of elements cut more than once;
//  - surface_traces.cpp: where cuts cross the mesh's edges and faces (elements cut again, 3D).
// Internal to those files; nothing else includes it.
#include <Eigen/Core>
#include <array>
#include <utility>
#include <vector>

#include "components/cut_elements.h"
#include "systems/surface/surface_cut.h"

namespace xcut::surface_cut_detail {

// --- surface_points.cpp ---
const int* local_edge(const World& w, int k);
int edge_count(const World& w);
bool holds(const World& w, int e, int node);
bool is_cut(const World& w, int e);
Vec3 rest_of(const World& w, int e, const Eigen::Vector4d& b);
Eigen::Vector4d local_bary(const World& w, const SurfaceMesh& s, int e, int v);
Vec3 vertex_rest(const World& w, const SurfaceMesh& s, int v);
/// Lists vertex v, just bound, among the vertices of its element's mesh element
/// (SurfaceMesh::bound_to), once: when that element is cut or cut again, v moves with it.
void note_bound(const World& w, SurfaceMesh& s, int v);
double surface_edge_param(int a, int b, double t);
double edge_crossing(const World& w, int a, int b);
/// Whether an edge may hold the crossings of several incisions: elements are cut again in 3D.
bool several_per_edge(const World& w);
/// Crossings closer than this (as fractions of their edge) are one [-].
inline constexpr double kSameCrossing = 1e-9;
/// Every crossing of mesh edge a -> b by a cut of an element round it (a cut once: its points; cut
/// again: each plane's own points, CutElements::line_edge_t), as the surface places them
/// (surface_edge_param), ascending, those within kSameCrossing of each other once; where an edge
/// holds one crossing (several_per_edge false), edge_crossing's, if any.
std::vector<double> edge_crossings(const World& w, int a, int b);
int surface_point(World& w, SurfaceMesh& s, int e, int side, const Eigen::Vector4d& b_in);
/// Whether the two sides of cut element e hold one copy of each node point b is weighted on (the
/// lips meet there; surface_points.cpp).
bool lips_joined(const World& w, int e, const Eigen::Vector4d& b);
/// The point where the lips part between surface vertices u and v of cut element e, on `side`
/// (their midpoint, one per side), where u and v are each one vertex of both lips (on the crack
/// front) but the lips are apart between them: a skin crossing (`skin`), or a cut-face edge not on
/// a face toward a whole element. Else -1: u-v is one edge of both lips. Without this point two
/// lips with both ends on the front would share that edge with the lips of the next element (an
/// edge of four triangles).
int parting_point(World& w, SurfaceMesh& s, int e, int side, int u, int v, bool skin);
void add_piece(SurfaceMesh& s, const std::array<int, 3>& t, int owner, bool cut);
/// The mesh element other than e holding the nodes of e's face opposite local node o (in 2D its
/// edge), or -1 (a face on the body's boundary).
int element_across(const World& w, int e, int o);
void remove_pieces(SurfaceMesh& s, const std::vector<int>& elements);
Eigen::Vector4d on_edge(int i, int j, double t);

/// Calls f(element) for every mesh element holding both nodes a and b (incidence order).
template <class F>
void for_elements_around(const World& w, int a, int b, F&& f) {
    for (int k = w.incidence.offset[a]; k < w.incidence.offset[a + 1]; ++k) {
        const int e = w.incidence.entry[k] >> 2;
        if (holds(w, e, b)) f(e);
    }
}

/// A point where a crack crosses a whole element's edge (local nodes i -> j, parameter t): its
/// skin triangles are split there (vertex v), so the sheet has no T-junction where a cut ends.
struct FrontPoint {
    int i, j, v;
    double t;
};

// --- surface_fragments.cpp (elements cut more than once) ---
/// The vertex at rest point `rest` (barycentric b in force element fe) for material `fe`: an
/// existing one there with the same copy of every mesh node b weighs, else a new one bound to fe
/// on `side`.
int shared_point(World& w, SurfaceMesh& s, int fe, int8_t side, const Eigen::Vector4d& b, const Vec3& rest);

/// Where elements are cut again in 3D: the triangles using two vertices bound to virtual elements
/// at one place (surface_place) with the same material (the same copy of each node they weigh) use
/// the first. A point's binding changes as the cuts around it go on (a crack front's opens, an
/// element's sides are cut again), so a point made for one material can later be another's twin.
void merge_material_twins(const World& w, SurfaceMesh& s);

/// The vertex at rest point `rest` (quantized: surface_place) of the material that virtual element
/// fe's binding at b has there (the same copy of each node it weighs), or -1.
int point_of_material(const World& w, const SurfaceMesh& s, int fe, const Eigen::Vector4d& b, const Vec3& rest);
// --- surface_traces.cpp (where cuts cross the mesh's edges and faces; elements cut again, 3D) ---
/// The rest corners of tetrahedron e.
std::array<Vec3, 4> rest_corners(const World& w, int e);
/// A point on a mesh edge of element e (barycentric b, two weights) near a cut's crossing of the
/// edge is that crossing (within 1e-4 of the edge, or 1.5 times the misfit of the planes round it).
void snap_to_crack(const World& w, int e, Eigen::Vector4d& b);
/// A skin corner at barycentric b of element e (two weights: on a mesh edge) where a crack crosses
/// that edge exactly: the surface placed the crossing off it (surface_edge_param), so the elements
/// cut once round it show the corner on the side of the edge's lower-numbered node and the crossing
/// past it. True then, with the crossing's barycentric coordinates and that node's local index.
bool corner_on_crossing(const World& w, int e, const Eigen::Vector4d& b, Eigen::Vector4d& crossing, int& kept);
/// A point on a face of element e (barycentric b, one weight zero) near two cuts' recorded traces
/// there (e's and the element's across) is where they cross; `size`: e's longest edge [m].
void snap_to_traces(const World& w, int e, double size, Eigen::Vector4d& b);

/// Cut element c's pieces, c having lines: its skin triangles clipped to each fragment, fanned; in
/// 3D also each fragment's faces on its cut planes.
void fragment_pieces(World& w, SurfaceMesh& s, int c);
/// Where the planes of the elements cut again across a face of element e (3D) cross the segment
/// a -> b on that face (rest; barycentric ba, bb in e), or of every element round the edge a -> b
/// lies on: (parameter from a, point), in order. A cut element's wound ends there on its face, and
/// e's own faces there must have that point too.
std::vector<std::pair<double, Vec3>> further_crossings(const World& w, int e, const Vec3& a, const Vec3& b,
                                                       const Eigen::Vector4d& ba, const Eigen::Vector4d& bb);
/// Splits the skin pieces of cut element c (cut once; 3D) where the planes of the elements cut
/// again around it cross its edges (further_crossings): another incision's wound ends on its skin.
void split_at_further_points(World& w, SurfaceMesh& s, int c, const CutPlaneInfo& cp);
/// Where the further lines of the cut elements around whole element e cross its edges, as its
/// front points.
std::vector<FrontPoint> further_front_points(World& w, SurfaceMesh& s, int e);

// --- surface_fronts.cpp ---
/// The zone elements (CrackTips indices) of each force element: z for `element`[z], chained.
struct ZoneIndex {
    std::vector<int> head, next;
    explicit ZoneIndex(const World& w) : head(w.elements.count(), -1), next(w.tips.zone(), -1) {
        for (int z = w.tips.zone() - 1; z >= 0; --z) next[z] = head[w.tips.element[z]], head[w.tips.element[z]] = z;
    }
};
/// Slits the surface inside the whole elements the crack behind each front runs through (3D; the
/// overlay's saved triangles set, `hidden` flagging the saved pieces taken off): new vertices and
/// triangles appended, the pieces they replace flagged in `hidden`. Returns the elements slit.
int slit_fronts(World& w, SurfaceMesh& s, const ZoneIndex& zi, std::vector<uint8_t>& hidden);

// --- surface_rim.cpp ---
double crossing_param(const World& w, const CutPlaneInfo& cp, int e, const Eigen::Vector4d& ba,
                      const Eigen::Vector4d& bb);

/// A skin crossing point of cut element e (barycentric b) and how far the skin triangle it was made
/// on lies off each face of e: off[a] = the triangle's largest weight on node a (0 for the face
/// opposite node a when the skin lies on it). A point on a mesh edge lies on two faces; its
/// triangle tells which one it belongs to.
struct RimPoint {
    Eigen::Vector4d b, off;
};

std::vector<Eigen::Vector4d> cut_rim_loop(const World& w, int e, const CutPlaneInfo& cp,
                                          const std::vector<Eigen::Vector4d>& edge_points,
                                          const std::vector<RimPoint>& rim);

// --- surface_cut_faces.cpp ---
/// Closes the wound inside cut c (3D): the cut face, one polygon per side over its edge points and
/// the skin crossings `rim`, oriented outward.
void cut_faces(World& w, SurfaceMesh& s, int c, const CutPlaneInfo& cp, const std::vector<RimPoint>& rim);

}  // namespace xcut::surface_cut_detail
