// The surface's points: the mesh around a cut element, and the vertices a cut makes, one per side
// and place, bound to the element of their side (paper §3.4; systems/surface/surface_cut_parts.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "systems/xfem_queries.h"
#include "systems/surface/surface_cut_parts.h"

namespace xcut {
namespace surface_cut_detail {
namespace {

constexpr double kQuantum = 1e-11;  // [m]: points closer than this on one side are one point

/// The element that holds the lips together at a point on mesh edge nodes[0]-nodes[1] (n = 2) or
/// at node nodes[0] (n = 1): the first whole (uncut) mesh element holding every node; else, on a
/// progressive front, the first cut element in which that edge (n = 1: an edge at that node) is split
/// but not yet crossed by the blade, whose nodes the crack-front rule holds. -1 if none.
int element_holding_lips(const World& w, const std::array<int, 4>& nodes, int n) {
    const int a = nodes[0];
    for (int k = w.incidence.offset[a]; k < w.incidence.offset[a + 1]; ++k) {
        const int e = w.incidence.entry[k] >> 2;
        if (is_cut(w, e)) continue;
        bool all = true;
        for (int i = 1; i < n; ++i) all = all && holds(w, e, nodes[i]);
        if (all) return e;
    }
    const auto& sign = w.enriched.sign;
    for (int k = w.incidence.offset[a]; k < w.incidence.offset[a + 1]; ++k) {
        const int e = w.incidence.entry[k] >> 2;
        if (!is_cut(w, e) || (n == 2 && !holds(w, e, nodes[1]))) continue;
        for (int m = 0; m < w.elements.nodes_per_element(); ++m) {
            const int b = w.elements.nodes[e][m];
            if ((n == 2 && b != nodes[1]) || sign[b] == sign[a]) continue;
            if (!edge_crossed(w, a, b)) return e;
        }
    }
    return -1;
}

/// Barycentric coordinates b (in element `from`'s node order) re-expressed in element `to`, which
/// holds every mesh node b is weighted on.
Eigen::Vector4d rebased(const World& w, int from, const Eigen::Vector4d& b, int to) {
    const int npe = w.elements.nodes_per_element();
    Eigen::Vector4d r = Eigen::Vector4d::Zero();
    for (int a = 0; a < npe; ++a) {
        if (b[a] == 0.0) continue;
        const int node = mesh_node(w, w.elements.nodes[from][a]);
        for (int k = 0; k < npe; ++k)
            if (w.elements.nodes[to][k] == node) r[k] += b[a];
    }
    return r;
}

/// Binds vertex v at barycentric b of mesh element e: to `whole` if that element holds the lips
/// together there (a crack-front point; a cut one through its upper virtual element, whose vertices
/// there are the held real nodes), else to the virtual element of cut element e on `side`.
void bind(World& w, SurfaceMesh& s, int v, int e, int side, const Eigen::Vector4d& b, int whole) {
    if (whole >= 0) {
        const int c = w.cuts.cut_of_element[whole];
        s.element[v] = c < 0 ? whole : w.virtual_elements.element[w.cuts.virtual_element[c][0]];
        s.bary[v] = rebased(w, e, b, whole);
    } else {
        const int c = w.cuts.cut_of_element[e];
        s.element[v] = w.virtual_elements.element[w.cuts.virtual_element[c][side > 0 ? 0 : 1]];
        s.bary[v] = b;
    }
    note_bound(w, s, v);
}

}  // namespace

/// Whether the two sides of cut element e hold the same material at a point weighted on e's
/// local nodes `on` (b != 0): both virtual elements name the same copy of each such node. Where
/// incisions end inside the body beside an element cut again, the material joins round the end
/// and node copies (systems/cut/node_copies.cpp) give both sides one copy though every element on
/// the edge is cut: the lips meet there as at a crack front, one vertex for both. So where
/// elements are cut again in 3D, whose fragments share points by material (surface_fragments.cpp),
/// and only there: elsewhere a cut's points are keyed by side and a whole element's hold (a short
/// slit's lips stay two; tests/systems/test_surface_cut.cpp, PartialIncisionScene).
bool lips_joined(const World& w, int e, const Eigen::Vector4d& b) {
    const int c = w.cuts.cut_of_element[e];
    if (c < 0 || w.elements.dim != 3 || !recut_allowed(w) || fragments_of(w, c).size() > 2) return false;
    const auto& up = w.elements.nodes[w.virtual_elements.element[w.cuts.virtual_element[c][0]]];
    const auto& down = w.elements.nodes[w.virtual_elements.element[w.cuts.virtual_element[c][1]]];
    for (int a = 0; a < w.elements.nodes_per_element(); ++a)
        if (b[a] != 0.0 && up[a] != down[a]) return false;
    return true;
}

const int* local_edge(const World& w, int k) { return w.elements.dim == 3 ? kTetEdges[k] : kTriEdges[k]; }

int edge_count(const World& w) { return w.elements.dim == 3 ? 6 : 3; }

bool holds(const World& w, int e, int node) {
    const auto& n = w.elements.nodes[e];
    return std::find(n.begin(), n.begin() + w.elements.nodes_per_element(), node) != n.begin() + w.elements.nodes_per_element();
}

bool is_cut(const World& w, int e) { return w.cuts.cut_of_element[e] >= 0; }

Vec3 rest_of(const World& w, int e, const Eigen::Vector4d& b) {
    Vec3 x = Vec3::Zero();
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) x += b[a] * w.nodes.rest[w.elements.nodes[e][a]];
    return x;
}

/// A vertex's barycentric coordinates in mesh element e (the vertex lies on e's boundary).
Eigen::Vector4d local_bary(const World& w, const SurfaceMesh& s, int e, int v) {
    return rebased(w, s.element[v], s.bary[v], e);
}

Vec3 vertex_rest(const World& w, const SurfaceMesh& s, int v) { return rest_of(w, s.element[v], s.bary[v]); }

void note_bound(const World& w, SurfaceMesh& s, int v) {
    const int e = mesh_element_of(w, s.element[v]);
    if (e < 0) return;
    std::vector<int>& list = s.bound_to[e];
    if (std::find(list.begin(), list.end(), v) == list.end()) list.push_back(v);
}

/// A crossing of mesh edge a -> b at parameter t, as the surface places it. A crossing on a skin
/// subdivision point (t = m / 2^k, k <= 8: the fallback midpoint of an edge crossed only through
/// its nodes' H, or a blade exactly there) moves by 1e-6 of the edge toward the higher-numbered
/// node, so no cut point sits on a skin vertex and every element sharing the edge agrees (a
/// crossing within 1e-9 of the edge's end stays: it is the node's vertex, as the plane through it
/// makes the skin's own crossings there). 1e-6 of
/// a millimetre edge is a nanometre: nothing to see, far beyond the 1e-11 m point quantum.
double surface_edge_param(int a, int b, double t) {
    const double m = std::round(t * 256.0);  // a crossing within 1e-9 of a node is that node's
    if (!(m >= 1.0 && m <= 255.0) || std::abs(t * 256.0 - m) > 256.0 * 1e-9) return t;
    return a < b ? t + 1e-6 : t - 1e-6;
}

/// The crossing of the mesh edge a -> b by the crack (crack_edge_param) as the surface places it
/// (surface_edge_param), or -1 if no cut element crosses it.
double edge_crossing(const World& w, int a, int b) {
    const double t = crack_edge_param(w, a, b);
    return t < 0.0 ? t : surface_edge_param(a, b, t);
}

bool several_per_edge(const World& w) { return w.elements.dim == 3 && recut_allowed(w); }

std::vector<double> edge_crossings(const World& w, int a, int b) {
    std::vector<double> out;
    if (!several_per_edge(w)) {
        if (const double t = edge_crossing(w, a, b); t > 0.0 && t < 1.0) out.push_back(t);
        return out;
    }
    for_elements_around(w, a, b, [&](int f) {  // every plane's own point on the edge
        const int c = w.cuts.cut_of_element[f];
        bool from_a = true;
        const int k = c >= 0 ? local_edge_of(w, f, a, b, from_a) : -1;
        for (size_t l = 0; k >= 0 && l < std::max<size_t>(1, w.cuts.lines[c].size()); ++l) {
            const double from = param_from(line_edge_params(w, c, l)[k], from_a);
            const double t = from < 0.0 ? -1.0 : surface_edge_param(a, b, from);
            if (t > 0.0 && t < 1.0 && std::none_of(out.begin(), out.end(), [&](double u) { return std::abs(u - t) < kSameCrossing; }))
                out.push_back(t);
        }
    });
    std::sort(out.begin(), out.end());
    return out;
}

/// The surface vertex at barycentric b of mesh element e on `side` of the cut, made once per side
/// and place (see SurfaceMesh::cut_point). A point on a mesh edge that a whole element still holds
/// (the crack front) is one vertex for both sides (side 0), bound to that element: the lips meet
/// there. Once no whole element holds the edge, that vertex becomes the copy of the first side
/// asked for, the other side gets its own, and the split is listed in SurfaceMesh::opened so that
/// every piece still using the shared vertex is made again. Otherwise a point is bound to the
/// virtual element of cut element e on its side.
int surface_point(World& w, SurfaceMesh& s, int e, int side, const Eigen::Vector4d& b_in) {
    const int npe = w.elements.nodes_per_element();
    // Weights below 1e-12 are round-off of re-expressing a point in another element: a point on an
    // edge or at a node is keyed and bound as such, whichever element computed it.
    Eigen::Vector4d b = b_in;
    for (int a = 0; a < npe; ++a)
        if (std::abs(b[a]) < 1e-12) b[a] = 0.0;
    b /= b.sum();
    std::array<int, 4> support{};
    int n = 0;
    for (int a = 0; a < npe; ++a)
        if (b[a] != 0.0) support[n++] = w.elements.nodes[e][a];
    // A cut through a node: on the node's own side the point is the node's base vertex, and on both
    // while a whole element holds the node (the lips meet there).
    if (n == 1 && s.node_vertex[support[0]] >= 0 &&
        (w.enriched.sign[support[0]] == side || element_holding_lips(w, support, 1) >= 0))
        return s.node_vertex[support[0]];
    // A cut through any other skin vertex (a subdivision point): that vertex, on its own side, or on
    // both while it is bound to a whole element (the crack front, where the lips meet).
    const std::array<int64_t, 3> place = surface_place(rest_of(w, e, b));
    if (const auto base = s.base_vertex_at.find(place);
        base != s.base_vertex_at.end() && (s.side[base->second] == side || s.side[base->second] == 0))
        return base->second;
    const int whole = n <= 2 ? element_holding_lips(w, support, n) : -1;
    const bool joined = whole < 0 && n <= 3 && lips_joined(w, e, b);
    const int key_side = whole >= 0 || joined ? 0 : side;
    const int64_t lo = std::min(support[0], support[n - 1]), hi = std::max(support[0], support[n - 1]);
    // Where several incisions may cross one edge, a point on it is also keyed by where (its weight
    // on the higher node, in steps of kSameCrossing); else one crossing per edge.
    int64_t along = 0;
    for (int a = 0; n == 2 && several_per_edge(w) && a < npe; ++a)
        if (w.elements.nodes[e][a] == hi) along = std::llround(b[a] / kSameCrossing);
    const std::array<int64_t, 4> key =
        n <= 2 ? std::array<int64_t, 4>{key_side, lo, hi, along} : std::array<int64_t, 4>{key_side + 4, place[0], place[1], place[2]};
    auto it = s.cut_point.find(key);
    if (it == s.cut_point.end() && n <= 2 && whole < 0 && !joined) {
        if (const auto front = s.cut_point.find({0, lo, hi, along}); front != s.cut_point.end()) {  // the front passed
            const int v = front->second;
            s.cut_point.erase(front);
            it = s.cut_point.emplace(key, v).first;
            s.side[v] = static_cast<int8_t>(side);
            s.opened.push_back({v, static_cast<int>(lo), static_cast<int>(hi)});
        }
    }
    if (w.elements.dim == 3 && recut_allowed(w)) {
        // A point an element cut again made there, of the material this one is bound to (its
        // pieces share points by material: surface_fragments.cpp), is this one; a vertex of this
        // key made before the material was the same (the binding moved since) gives way to it,
        // and the pieces using that vertex are made again (SurfaceMesh::opened).
        const int at = whole >= 0 ? whole : e, c = w.cuts.cut_of_element[at];
        const int fe = c < 0 ? at : w.virtual_elements.element[w.cuts.virtual_element[c][whole >= 0 || side > 0 ? 0 : 1]];
        const Eigen::Vector4d bb = whole >= 0 ? rebased(w, e, b, whole) : b;
        if (const int v = point_of_material(w, s, fe, bb, rest_of(w, e, b)); v >= 0) {
            if (it == s.cut_point.end()) it = s.cut_point.emplace(key, v).first;
            else if (it->second != v) s.opened.push_back({it->second, support[0], support[n - 1]}), it->second = v;
        }
    }
    if (it == s.cut_point.end()) {
        // A node's copy for the side across from its own: pieces made while the lips met at the
        // node's base vertex (a whole element held it) are made again.
        if (n == 1 && s.node_vertex[support[0]] >= 0)
            s.opened.push_back({s.node_vertex[support[0]], support[0], support[0]});
        it = s.cut_point.emplace(key, s.vertex_count()).first;
        s.point_at.emplace(place, s.vertex_count());
        s.position.push_back(rest_of(w, e, b));
        s.element.push_back(-1);
        s.bary.emplace_back();
        s.side.push_back(static_cast<int8_t>(key_side));
    }
    bind(w, s, it->second, e, side, b, whole);
    return it->second;
}

/// Adds triangle t to `owner`'s pieces; one with a repeated vertex (a cut through a node or along
/// an edge collapses it) is not a triangle and is dropped.
void add_piece(SurfaceMesh& s, const std::array<int, 3>& t, int owner, bool cut) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return;
    s.pieces_of[owner].push_back(static_cast<int>(s.triangles.size()));
    s.triangles.push_back(t);
    s.triangle_owner.push_back(owner);
    s.cut_face.push_back(cut ? 1 : 0);
}

/// Removes every output triangle of the given elements (swap with the last, fixing its index).
void remove_pieces(SurfaceMesh& s, const std::vector<int>& elements) {
    std::vector<int> doomed;
    for (int e : elements) {
        doomed.insert(doomed.end(), s.pieces_of[e].begin(), s.pieces_of[e].end());
        s.pieces_of[e].clear();
    }
    std::sort(doomed.rbegin(), doomed.rend());
    for (int t : doomed) {
        const int last = static_cast<int>(s.triangles.size()) - 1;
        if (t != last) {  // `last` is no doomed triangle: those above t are gone already
            s.triangles[t] = s.triangles[last];
            s.triangle_owner[t] = s.triangle_owner[last];
            s.cut_face[t] = s.cut_face[last];
            auto& list = s.pieces_of[s.triangle_owner[t]];
            *std::find(list.begin(), list.end(), last) = t;
        }
        s.triangles.pop_back();
        s.triangle_owner.pop_back();
        s.cut_face.pop_back();
    }
}

/// Point on local edge (i, j) of e at parameter t from i, as barycentric coordinates.
Eigen::Vector4d on_edge(int i, int j, double t) {
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    b[i] = 1.0 - t;
    b[j] = t;
    return b;
}

int element_across(const World& w, int e, int o) {
    const int npe = w.elements.nodes_per_element();
    const auto& en = w.elements.nodes[e];
    std::array<int, 3> face{};
    for (int a = 0, m = 0; a < npe; ++a)
        if (a != o) face[m++] = en[a];
    for (int k = w.incidence.offset[face[0]]; k < w.incidence.offset[face[0] + 1]; ++k) {
        const int f = w.incidence.entry[k] >> 2;
        bool all = f != e;
        for (int m = 1; m < npe - 1; ++m) all = all && holds(w, f, face[m]);
        if (all) return f;
    }
    return -1;
}

int parting_point(World& w, SurfaceMesh& s, int e, int side, int u, int v, bool skin) {
    if (u == v) return -1;
    const Eigen::Vector4d bu = local_bary(w, s, e, u), bv = local_bary(w, s, e, v);
    if (!skin) {  // a cut face's edge: on the front when it lies on a face of e toward a whole element
        for (int o = 0; o < w.elements.nodes_per_element(); ++o)
            if (std::abs(bu[o]) < 1e-9 && std::abs(bv[o]) < 1e-9) {
                const int f = element_across(w, e, o);
                if (f >= 0 && !is_cut(w, f)) return -1;
            }
    }
    const int mid = surface_point(w, s, e, side, 0.5 * (bu + bv));
    return s.side[mid] == 0 ? -1 : mid;  // the midpoint is on the front too (u-v along a mesh edge)
}

}  // namespace surface_cut_detail

std::array<int64_t, 3> surface_place(const Vec3& x) {
    using surface_cut_detail::kQuantum;
    return {std::llround(x.x() / kQuantum), std::llround(x.y() / kQuantum), std::llround(x.z() / kQuantum)};
}

}  // namespace xcut
