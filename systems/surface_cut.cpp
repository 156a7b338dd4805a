#include "systems/surface_cut.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "components/cut_elements.h"
#include "systems/enrichment_system.h"

namespace xcut {
namespace {

constexpr double kQuantum = 1e-11;  // [m]: points closer than this on one side are one point

const int* local_edge(const World& w, int k) { return w.elements.dim == 3 ? kTetEdges[k] : kTriEdges[k]; }
int edge_count(const World& w) { return w.elements.dim == 3 ? 6 : 3; }

int mesh_node(const World& w, int node) {
    return node >= w.mesh_nodes ? w.enriched.node_of_phantom[node - w.mesh_nodes] : node;
}

bool holds(const World& w, int e, int node) {
    const auto& n = w.elements.nodes[e];
    return std::find(n.begin(), n.begin() + w.elements.nodes_per_element(), node) != n.begin() + w.elements.nodes_per_element();
}

bool is_cut(const World& w, int e) { return w.cuts.cut_of_element[e] >= 0; }

/// Calls f(element) for every mesh element holding both nodes a and b (incidence order).
template <class F>
void for_elements_around(const World& w, int a, int b, F&& f) {
    for (int k = w.incidence.offset[a]; k < w.incidence.offset[a + 1]; ++k) {
        const int e = w.incidence.entry[k] >> 2;
        if (holds(w, e, b)) f(e);
    }
}

/// The first whole (uncut) mesh element holding every node of `nodes` [0, n), or -1.
int whole_element_holding(const World& w, const std::array<int, 4>& nodes, int n) {
    for (int k = w.incidence.offset[nodes[0]]; k < w.incidence.offset[nodes[0] + 1]; ++k) {
        const int e = w.incidence.entry[k] >> 2;
        if (is_cut(w, e)) continue;
        bool all = true;
        for (int i = 1; i < n; ++i) all = all && holds(w, e, nodes[i]);
        if (all) return e;
    }
    return -1;
}

Vec3 rest_of(const World& w, int e, const Eigen::Vector4d& b) {
    Vec3 x = Vec3::Zero();
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) x += b[a] * w.nodes.rest[w.elements.nodes[e][a]];
    return x;
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

/// A vertex's barycentric coordinates in mesh element e (the vertex lies on e's boundary).
Eigen::Vector4d local_bary(const World& w, const SurfaceMesh& s, int e, int v) {
    return rebased(w, s.element[v], s.bary[v], e);
}

Vec3 vertex_rest(const World& w, const SurfaceMesh& s, int v) { return rest_of(w, s.element[v], s.bary[v]); }

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

/// Binds vertex v at barycentric b of mesh element e: to `whole` if that whole element holds it (a
/// crack-front point), else to the virtual element of cut element e on `side`.
void bind(World& w, SurfaceMesh& s, int v, int e, int side, const Eigen::Vector4d& b, int whole) {
    if (whole >= 0) {
        s.element[v] = whole;
        s.bary[v] = rebased(w, e, b, whole);
    } else {
        const int c = w.cuts.cut_of_element[e];
        s.element[v] = w.virtual_elements.element[w.cuts.virtual_element[c][side > 0 ? 0 : 1]];
        s.bary[v] = b;
    }
}

/// The surface vertex at barycentric b of mesh element e on `side` of the cut, made once per side
/// and place (see SurfaceMesh::cut_point). A point on a mesh edge that a whole element still holds
/// (the crack front) is bound, for both sides, to that element: the lips meet there. Otherwise it
/// is bound to the virtual element of cut element e on its side.
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
    // A cut through a node: on the node's own side the point is the node's base vertex.
    if (n == 1 && w.enriched.sign[support[0]] == side && s.node_vertex[support[0]] >= 0) return s.node_vertex[support[0]];
    // A cut through any other skin vertex (a subdivision point): that vertex, on its own side, or on
    // both while it is bound to a whole element (the crack front, where the lips meet).
    const std::array<int64_t, 3> place = surface_place(rest_of(w, e, b));
    if (const auto base = s.base_vertex_at.find(place);
        base != s.base_vertex_at.end() && (s.side[base->second] == side || s.side[base->second] == 0))
        return base->second;
    std::array<int64_t, 4> key;
    if (n <= 2)
        key = {side, std::min(support[0], support[n - 1]), std::max(support[0], support[n - 1]), 0};
    else
        key = {side + 4, place[0], place[1], place[2]};
    auto [it, fresh] = s.cut_point.emplace(key, s.vertex_count());
    if (fresh) {
        s.position.push_back(rest_of(w, e, b));
        s.element.push_back(-1);
        s.bary.emplace_back();
        s.side.push_back(static_cast<int8_t>(side));
    }
    bind(w, s, it->second, e, side, b, n <= 2 ? whole_element_holding(w, support, n) : -1);
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

/// The cut's level at rest point x on the face of cut element e opposite local node o, by the
/// trace the cut leaves on that face: the line through the two edge points on its edges (the
/// plane through all of them need not hold both when the points are not coplanar). Positive on
/// the H = +1 side. False if the face holds no such trace (3D only).
bool face_trace_level(const World& w, const CutPlaneInfo& cp, int e, int o, const Vec3& x, double& level) {
    if (w.elements.dim != 3) return false;
    const auto& en = w.elements.nodes[e];
    std::array<Vec3, 2> trace;
    int n = 0;
    for (size_t k = 0; k < cp.points.size(); ++k) {
        const int* ed = kTetEdges[cp.point_edge[k]];
        if (ed[0] == o || ed[1] == o) continue;
        if (n == 2) return false;
        trace[n++] = cp.points[k];
    }
    const Vec3 along = n == 2 ? Vec3(trace[1] - trace[0]) : Vec3::Zero();
    std::array<int, 3> face{};
    for (int a = 0, m = 0; a < 4; ++a)
        if (a != o) face[m++] = a;
    const Vec3 normal = (w.nodes.rest[en[face[1]]] - w.nodes.rest[en[face[0]]]).cross(w.nodes.rest[en[face[2]]] - w.nodes.rest[en[face[0]]]);
    const Vec3 across = normal.cross(along);  // in the face, normal to the trace
    if (n != 2 || across.norm() <= 1e-12 * normal.norm() * std::max(along.norm(), 1e-300)) return false;
    int far = face[0];
    for (int a : face)
        if (std::abs(across.dot(w.nodes.rest[en[a]] - trace[0])) > std::abs(across.dot(w.nodes.rest[en[far]] - trace[0]))) far = a;
    const double at_far = across.dot(w.nodes.rest[en[far]] - trace[0]);
    if (at_far == 0.0) return false;
    level = across.dot(x - trace[0]) * ((at_far > 0) == (w.enriched.sign[en[far]] > 0) ? 1.0 : -1.0);
    return true;
}

/// The local node a point at barycentric b is not weighted on when it lies inside one face of e
/// (exactly one zero weight), else -1.
int face_of(const Eigen::Vector4d& b) {
    int o = -1;
    for (int a = 0; a < 4; ++a)
        if (b[a] == 0.0) {
            if (o >= 0) return -1;
            o = a;
        }
    return o;
}

/// Where the skin edge a -> b meets the cut (parameter along a -> b). An edge lying on a crossed
/// element edge uses that edge's own intersection point, so skin and cut faces meet exactly.
double crossing_param(const World& w, const CutPlaneInfo& cp, int e, const Eigen::Vector4d& ba,
                      const Eigen::Vector4d& bb) {
    const int npe = w.elements.nodes_per_element();
    std::array<int, 4> support{};
    int n = 0;
    for (int a = 0; a < npe; ++a)
        if (ba[a] != 0.0 || bb[a] != 0.0) support[n++] = a;
    if (n == 2) {
        const int i = support[0], j = support[1];
        for (size_t k = 0; k < cp.points.size(); ++k) {
            const int* ed = local_edge(w, cp.point_edge[k]);
            if (!((ed[0] == i && ed[1] == j) || (ed[0] == j && ed[1] == i))) continue;
            // The point's barycentric weight on node j, and those of a and b: solve along the edge.
            const Vec3 Xi = w.nodes.rest[w.elements.nodes[e][i]], Xj = w.nodes.rest[w.elements.nodes[e][j]];
            const double tp = (cp.points[k] - Xi).dot(Xj - Xi) / (Xj - Xi).squaredNorm();
            const double ta = ba[j], tb = bb[j];
            if (ta == tb) break;
            return std::clamp((tp - ta) / (tb - ta), 0.0, 1.0);
        }
    }
    double la = 0.0, lb = 0.0;
    // A skin edge inside one face (both ends off the same node) crosses the cut's trace there.
    for (int o = 0; n == 3 && o < npe; ++o)
        if (ba[o] == 0.0 && bb[o] == 0.0 && face_trace_level(w, cp, e, o, rest_of(w, e, ba), la) &&
            face_trace_level(w, cp, e, o, rest_of(w, e, bb), lb))
            return la != lb ? std::clamp(la / (la - lb), 0.0, 1.0) : 0.5;
    la = lb = 0.0;
    for (int a = 0; a < npe; ++a) la += ba[a] * cp.phi[a], lb += bb[a] * cp.phi[a];
    return la != lb ? std::clamp(la / (la - lb), 0.0, 1.0) : 0.5;
}

/// Point on local edge (i, j) of e at parameter t from i, as barycentric coordinates.
Eigen::Vector4d on_edge(int i, int j, double t) {
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    b[i] = 1.0 - t;
    b[j] = t;
    return b;
}

/// The mesh element other than e holding nodes a, b, c, or -1 (a face on the body's boundary).
int element_across(const World& w, int e, int a, int b, int c) {
    for (int k = w.incidence.offset[a]; k < w.incidence.offset[a + 1]; ++k) {
        const int f = w.incidence.entry[k] >> 2;
        if (f != e && holds(w, f, b) && holds(w, f, c)) return f;
    }
    return -1;
}

/// Whether a cut element shows skin on a face along mesh edge a-b: the incision reaches the body's
/// surface there. Otherwise the cut touches the edge inside the body only (the crack meets the
/// surface in one point) and the skin on both sides of the edge keeps one copy of the point: the
/// crack's two lips meet it through the seams (front_seams), which then close the crack by
/// themselves, and the skin stays one sheet (a zero-length edge shared by four triangles
/// otherwise).
bool skin_cut_along(const World& w, int a, int b) {
    bool cut_skin = false;
    for_elements_around(w, a, b, [&](int f) {
        if (cut_skin || !is_cut(w, f)) return;
        for (int k = 0; k < w.elements.nodes_per_element(); ++k) {
            const int third = w.elements.nodes[f][k];
            if (third == a || third == b) continue;
            if (w.elements.dim == 2 || element_across(w, f, a, b, third) < 0) cut_skin = true;
        }
    });
    return cut_skin;
}

/// A whole element's pieces: its skin triangles, each split at the crack-front points on its
/// edges. Triangle a-b-c with the front point P inside a-b becomes a-Pa-c, Pa-Pb-c, Pb-b-c, with Pa
/// and Pb the copies of P on a's and b's side of the cut: both are bound to this whole element, so
/// the middle triangle has no area until the front moves on and the lips part.
void whole_element_pieces(World& w, SurfaceMesh& s, int e) {
    if (s.base_of[e].empty()) return;
    const auto& en = w.elements.nodes[e];
    struct FrontPoint { int i, j, vi, vj; double t; };  // vi: the copy on node i's side
    std::vector<FrontPoint> front;
    for (int k = 0; k < edge_count(w); ++k) {
        const int i = local_edge(w, k)[0], j = local_edge(w, k)[1];
        const double t = edge_crossing(w, en[i], en[j]);
        if (!(t > 0.0 && t < 1.0)) continue;
        int hi = w.enriched.sign[en[i]] >= 0 ? 1 : -1, hj = w.enriched.sign[en[j]] >= 0 ? 1 : -1;
        if (!skin_cut_along(w, en[i], en[j])) hi = hj = (en[i] < en[j] ? hi : hj);
        const Eigen::Vector4d b = on_edge(i, j, t);
        front.push_back({i, j, surface_point(w, s, e, hi, b), surface_point(w, s, e, hj, b), t});
    }
    std::vector<std::array<int, 3>> pieces;
    for (int bt : s.base_of[e]) {
        pieces.assign(1, s.base_triangles[bt]);
        for (const FrontPoint& p : front)
            for (size_t q = 0; q < pieces.size(); ++q) {
                const auto tri = pieces[q];
                int split = -1;
                double ta = 0.0;
                for (int k = 0; k < 3 && split < 0; ++k) {
                    const Eigen::Vector4d ba = local_bary(w, s, e, tri[k]), bb = local_bary(w, s, e, tri[(k + 1) % 3]);
                    const bool on_ij = std::abs(ba[p.i] + ba[p.j] - 1.0) < 1e-12 && std::abs(bb[p.i] + bb[p.j] - 1.0) < 1e-12;
                    if (on_ij && (ba[p.j] - p.t) * (bb[p.j] - p.t) < 0.0) split = k, ta = ba[p.j];
                }
                if (split < 0) continue;
                const int a = tri[split], b = tri[(split + 1) % 3], c = tri[(split + 2) % 3];
                const int pa = ta < p.t ? p.vi : p.vj, pb = ta < p.t ? p.vj : p.vi;
                pieces[q] = {a, pa, c};
                if (pa != pb) pieces.push_back({pa, pb, c});
                pieces.push_back({pb, b, c});
                break;
            }
        for (const auto& t : pieces) add_piece(s, t, e, false);
    }
}

/// Outward faces of a positively oriented tetrahedron, as local node triples.
constexpr int kTetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// Closes the two lips of cut element e along its crack front: on each face of e toward a whole
/// element, the cut's segment P-Q exists once per side (P+ Q+ in the fan above, P- Q- below); a
/// seam quad Q+ P+ P- Q- joins them, oriented against the fans' directed edges. It has no area
/// while the front holds (both copies bound to the whole neighbour).
void front_seams(World& w, SurfaceMesh& s, int c, const std::vector<std::pair<int, int>>& fan_edges,
                 const std::vector<Eigen::Vector4d>& edge_points, const std::vector<int>& point_edge) {
    const int e = w.cuts.element[c];
    const auto& en = w.elements.nodes[e];
    for (const auto& face : kTetFaces) {
        std::vector<int> on_face;
        for (size_t k = 0; k < point_edge.size(); ++k) {
            const int* ed = kTetEdges[point_edge[k]];
            const bool inside = std::count(face, face + 3, ed[0]) && std::count(face, face + 3, ed[1]);
            if (inside) on_face.push_back(static_cast<int>(k));
        }
        if (on_face.size() != 2) continue;
        const int f = element_across(w, e, en[face[0]], en[face[1]], en[face[2]]);
        if (f < 0 || is_cut(w, f)) continue;
        int pp = surface_point(w, s, e, 1, edge_points[on_face[0]]);
        int qp = surface_point(w, s, e, 1, edge_points[on_face[1]]);
        int pm = surface_point(w, s, e, -1, edge_points[on_face[0]]);
        int qm = surface_point(w, s, e, -1, edge_points[on_face[1]]);
        if (std::find(fan_edges.begin(), fan_edges.end(), std::make_pair(qp, pp)) != fan_edges.end()) {
            std::swap(pp, qp);
            std::swap(pm, qm);
        }
        // Now the fan above holds P+ -> Q+ and the one below Q- -> P-.
        add_piece(s, {qp, pp, pm}, e, true);
        add_piece(s, {qp, pm, qm}, e, true);
    }
}

}  // namespace

int side_of_cut(const World& w, const CutPlaneInfo& cp, int e, const Eigen::Vector4d& b) {
    const int npe = w.elements.nodes_per_element();
    const auto& en = w.elements.nodes[e];
    for (int a = 0; a < npe; ++a)
        if (b[a] == 1.0) return w.enriched.sign[en[a]];
    // On a mesh edge, every element holding the edge must agree: decide by the nodes' H and the
    // edge's own crossing, not by this element's plane.
    int i = -1, j = -1;
    for (int a = 0; a < npe; ++a)
        if (b[a] != 0.0) (i < 0 ? i : j) = a;
    if (j >= 0 && b[i] + b[j] == 1.0) {
        const int hi = w.enriched.sign[en[i]], hj = w.enriched.sign[en[j]];
        if (hi == hj && hi != 0) return hi;
        const double t = edge_crossing(w, en[i], en[j]);  // from node i
        if (hi != 0 && hj != 0 && t > 0.0 && t < 1.0) {
            if (b[j] != t) return b[j] < t ? hi : hj;
            return en[i] < en[j] ? hi : hj;  // exactly at the crossing: the lower node's side, whoever asks
        }
    }
    double level = 0.0;
    if (npe == 4) {  // inside a face: by the cut's trace on it, as the skin's crossings are made
        const int o = face_of(b);
        if (o >= 0 && face_trace_level(w, cp, e, o, rest_of(w, e, b), level)) return level >= 0.0 ? 1 : -1;
    }
    for (int a = 0; a < npe; ++a) level += b[a] * cp.phi[a];
    return cp.orient * level >= 0.0 ? 1 : -1;
}

namespace {

/// Triangulates one side's cut polygon `loop` (outward order) of cut element e: three points give
/// one triangle, four give two split along the diagonal the Delaunay criterion picks (the angles
/// facing it sum to less than pi), more (skin crossing points on the rim) a fan around the centre.
void close_polygon(World& w, SurfaceMesh& s, int e, int side, const std::vector<int>& loop,
                   const Eigen::Vector4d& centre) {
    if (loop.size() == 3) {
        add_piece(s, {loop[0], loop[1], loop[2]}, e, true);
        return;
    }
    if (loop.size() == 4) {
        auto angle = [&](int at, int p, int q) {
            const Vec3 x = vertex_rest(w, s, at);
            const Vec3 a = vertex_rest(w, s, p) - x, b = vertex_rest(w, s, q) - x;
            return std::atan2(a.cross(b).norm(), a.dot(b));
        };
        const auto& l = loop;
        if (angle(l[1], l[0], l[2]) + angle(l[3], l[2], l[0]) <= M_PI) {  // diagonal 0-2
            add_piece(s, {l[0], l[1], l[2]}, e, true);
            add_piece(s, {l[0], l[2], l[3]}, e, true);
        } else {  // diagonal 1-3
            add_piece(s, {l[1], l[2], l[3]}, e, true);
            add_piece(s, {l[1], l[3], l[0]}, e, true);
        }
        return;
    }
    const int hub = surface_point(w, s, e, side, centre);
    for (size_t k = 0; k < loop.size(); ++k) add_piece(s, {hub, loop[k], loop[(k + 1) % loop.size()]}, e, true);
}

/// The edge points of cut element e as the surface uses them (surface_edge_param), and the plane
/// through them: a skin vertex the cut passes through (a subdivision point the crossing was moved
/// off) then lies clearly on the side its edge's crossing gives it, so the skin's own crossings
/// near it are made on the cut, not at the vertex.
/// The plane through cp.points (their centroid; 2D: normal to the segment, 3D: the largest normal
/// of any three points, as a quad's points stored by edge may be a bow-tie where Newell's sum
/// cancels) and each node's level and the orientation, for cut element e.
void fit_cut_plane(const World& w, int e, CutPlaneInfo& cp) {
    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    const auto& p = cp.points;
    cp.origin = Vec3::Zero();
    cp.normal = Vec3::Zero();
    for (const Vec3& x : p) cp.origin += x / static_cast<double>(p.size());
    if (el.dim == 2) {
        const Vec3 d = p[1] - p[0];
        cp.normal = Vec3(-d.y(), d.x(), 0.0);
    } else {
        for (size_t i = 1; i < p.size(); ++i)
            for (size_t j = i + 1; j < p.size(); ++j) {
                const Vec3 m = (p[i] - p[0]).cross(p[j] - p[0]);
                if (m.squaredNorm() > cp.normal.squaredNorm()) cp.normal = m;
            }
    }
    cp.normal.normalize();
    int far = 0;
    for (int a = 0; a < npe; ++a) {
        cp.phi[a] = cp.normal.dot(w.nodes.rest[el.nodes[e][a]] - cp.origin);
        if (std::abs(cp.phi[a]) > std::abs(cp.phi[far])) far = a;
    }
    cp.orient = (cp.phi[far] >= 0) == (w.enriched.sign[el.nodes[e][far]] > 0) ? 1.0 : -1.0;
}

void keep_off_skin_vertices(const World& w, int e, CutPlaneInfo& cp) {
    for (size_t k = 0; k < cp.points.size(); ++k) {
        const int* ed = local_edge(w, cp.point_edge[k]);
        const int a = w.elements.nodes[e][ed[0]], b = w.elements.nodes[e][ed[1]];
        const Vec3 &Xa = w.nodes.rest[a], &Xb = w.nodes.rest[b];
        const double t = (cp.points[k] - Xa).dot(Xb - Xa) / (Xb - Xa).squaredNorm();
        cp.points[k] = Xa + surface_edge_param(a, b, t) * (Xb - Xa);
    }
    fit_cut_plane(w, e, cp);
}

/// A cut element's pieces: its skin triangles split per side, then (3D) the internal mesh: edge
/// points and rim points around the cut, a fan per side.

/// A skin crossing point of cut element e (barycentric b) and how far the skin triangle it was made
/// on lies off each face of e: off[a] = the triangle's largest weight on node a (0 for the face
/// opposite node a when the skin lies on it). A point on a mesh edge lies on two faces; its
/// triangle tells which one it belongs to.
struct RimPoint {
    Eigen::Vector4d b, off;
};

/// The rim of cut element e's cut face, counter-clockwise about the cut's normal: its edge points
/// in angular order (3 or 4 points on distinct edges of the tetrahedron: a convex polygon seen
/// along the normal), and between two consecutive ones P, Q the skin crossing points of the face
/// holding both, in order along P -> Q. The skin's crossings need not lie on the plane through the
/// edge points (a fallback midpoint, a curved blade path), so they are not sorted by angle: a rim
/// that bends around the centre would come out crossed.
std::vector<Eigen::Vector4d> cut_rim_loop(const World& w, int e, const CutPlaneInfo& cp,
                                          const std::vector<Eigen::Vector4d>& edge_points,
                                          const std::vector<RimPoint>& rim) {
    const Vec3 u = cp.normal.unitOrthogonal(), v = cp.normal.cross(u);
    auto by_angle = [&](std::vector<Eigen::Vector4d> points) {
        Vec3 xc = Vec3::Zero();
        for (const auto& b : points) xc += rest_of(w, e, b) / static_cast<double>(points.size());
        std::vector<std::pair<double, int>> order;
        for (size_t k = 0; k < points.size(); ++k) {
            const Vec3 d = rest_of(w, e, points[k]) - xc;
            order.emplace_back(std::atan2(d.dot(v), d.dot(u)), static_cast<int>(k));
        }
        std::sort(order.begin(), order.end());
        std::vector<Eigen::Vector4d> sorted;
        for (const auto& [angle, k] : order) sorted.push_back(points[k]);
        return sorted;
    };
    // Edge points at nodes (a cut through a node, or along a face) make no polygon to anchor the
    // rim on: there the rim points lie on the plane through the nodes, and sort by angle. So do
    // the points of a 2D cut.
    const bool at_node = std::any_of(edge_points.begin(), edge_points.end(), [](const auto& b) { return b.maxCoeff() > 1.0 - 1e-12; });
    if (edge_points.size() < 3 || at_node) {
        std::vector<Eigen::Vector4d> all;
        for (const RimPoint& r : rim) all.push_back(r.b);
        all.insert(all.end(), edge_points.begin(), edge_points.end());
        return by_angle(all);
    }
    // Around the polygon of edge points, neighbours lie on edges sharing a face (a quad's points on
    // opposite edges are its diagonal); counter-clockwise about the normal. Not by angle: points
    // off the plane (a fallback midpoint) can make the angular order a bow-tie.
    std::vector<int> order = {0};
    for (size_t step = 1; step < edge_points.size(); ++step) {
        const int* last = kTetEdges[cp.point_edge[order.back()]];
        for (int k = 0; k < static_cast<int>(edge_points.size()); ++k) {
            const int* ed = kTetEdges[cp.point_edge[k]];
            const bool share_face = ed[0] == last[0] || ed[0] == last[1] || ed[1] == last[0] || ed[1] == last[1];
            if (share_face && std::find(order.begin(), order.end(), k) == order.end()) {
                order.push_back(k);
                break;
            }
        }
    }
    Vec3 newell = Vec3::Zero();
    for (size_t k = 0; k < order.size(); ++k)
        newell += rest_of(w, e, edge_points[order[k]]).cross(rest_of(w, e, edge_points[order[(k + 1) % order.size()]]));
    if (newell.dot(cp.normal) < 0.0) std::reverse(order.begin(), order.end());
    std::vector<Eigen::Vector4d> anchors;
    for (int k : order) anchors.push_back(edge_points[k]);
    const size_t n = anchors.size();
    // The face holding both P_k and P_k+1 is the one opposite the node neither point is weighted
    // on (none for points on opposite edges).
    std::vector<Eigen::Vector4d> apart(n);
    for (size_t k = 0; k < n; ++k) apart[k] = anchors[k].cwiseAbs() + anchors[(k + 1) % n].cwiseAbs();
    std::vector<std::vector<std::pair<double, int>>> between(n);
    for (size_t r = 0; r < rim.size(); ++r) {
        size_t best = 0;
        double off = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k < n; ++k)  // the face its skin triangle lies on: least weight off it
            for (int a = 0; a < w.elements.nodes_per_element(); ++a)
                if (apart[k][a] == 0.0 && rim[r].off[a] < off) off = rim[r].off[a], best = k;
        const Vec3 P = rest_of(w, e, anchors[best]), Q = rest_of(w, e, anchors[(best + 1) % n]);
        between[best].emplace_back((rest_of(w, e, rim[r].b) - P).dot(Q - P), static_cast<int>(r));
    }
    std::vector<Eigen::Vector4d> loop;
    for (size_t k = 0; k < n; ++k) {
        loop.push_back(anchors[k]);
        std::sort(between[k].begin(), between[k].end());
        for (const auto& [along, r] : between[k]) loop.push_back(rim[r].b);
    }
    return loop;
}

void cut_element_pieces(World& w, SurfaceMesh& s, int c) {
    const int e = w.cuts.element[c];
    const CutPlaneInfo cp = cut_plane_info(w, c);
    std::vector<RimPoint> rim;  // skin crossing points, for the cut faces' rims
    for (int bt : s.base_of[e]) {
        const auto tri = s.base_triangles[bt];
        std::array<int, 3> side;
        std::array<Eigen::Vector4d, 3> lb;
        for (int k = 0; k < 3; ++k) {
            lb[k] = local_bary(w, s, e, tri[k]);
            side[k] = side_of_cut(w, cp, e, lb[k]);
        }
        int lone = -1;
        for (int k = 0; k < 3; ++k)
            if (side[k] != side[(k + 1) % 3] && side[k] != side[(k + 2) % 3]) lone = k;
        if (lone < 0) {  // not crossed: kept whole
            add_piece(s, tri, e, false);
            continue;
        }
        const int L = tri[lone], M1 = tri[(lone + 1) % 3], M2 = tri[(lone + 2) % 3];
        const Eigen::Vector4d &bL = lb[lone], &bM1 = lb[(lone + 1) % 3], &bM2 = lb[(lone + 2) % 3];
        const double s1 = crossing_param(w, cp, e, bL, bM1);
        const double s2 = crossing_param(w, cp, e, bL, bM2);
        const Eigen::Vector4d b1 = (1 - s1) * bL + s1 * bM1;
        const Eigen::Vector4d b2 = (1 - s2) * bL + s2 * bM2;
        const Eigen::Vector4d off = lb[0].cwiseAbs().cwiseMax(lb[1].cwiseAbs()).cwiseMax(lb[2].cwiseAbs());
        rim.push_back({b1, off});
        rim.push_back({b2, off});
        const int sl = side[lone], sm = -sl;
        const int x1l = surface_point(w, s, e, sl, b1), x2l = surface_point(w, s, e, sl, b2);
        const int x1m = surface_point(w, s, e, sm, b1), x2m = surface_point(w, s, e, sm, b2);
        add_piece(s, {L, x1l, x2l}, e, false);
        add_piece(s, {x1m, M1, M2}, e, false);
        add_piece(s, {x1m, M2, x2m}, e, false);
    }
    if (w.elements.dim == 2) return;  // in 2D the surface is the sheet itself: the gap is the cut

    std::vector<Eigen::Vector4d> edge_points;
    const auto& nodes = w.elements.nodes[e];
    for (size_t k = 0; k < cp.points.size(); ++k) {
        const int* ed = kTetEdges[cp.point_edge[k]];
        const Vec3 Xi = w.nodes.rest[nodes[ed[0]]], Xj = w.nodes.rest[nodes[ed[1]]];
        edge_points.push_back(on_edge(ed[0], ed[1], (cp.points[k] - Xi).dot(Xj - Xi) / (Xj - Xi).squaredNorm()));
    }
    std::vector<std::pair<int, int>> fan_edges;  // directed loop edges of both fans
    Eigen::Vector4d centre = Eigen::Vector4d::Zero();
    for (const RimPoint& r : rim) centre += r.b / static_cast<double>(rim.size() + edge_points.size());
    for (const auto& b : edge_points) centre += b / static_cast<double>(rim.size() + edge_points.size());
    const std::vector<Eigen::Vector4d> around = cut_rim_loop(w, e, cp, edge_points, rim);
    for (int side : {1, -1}) {
        std::vector<int> loop;
        for (const Eigen::Vector4d& b : around) {
            const int id = surface_point(w, s, e, side, b);
            // Each point once: a rim point at an edge point's place (the skin's crossing on a
            // crossed element edge) is that point.
            if (std::find(loop.begin(), loop.end(), id) == loop.end()) loop.push_back(id);
        }
        if (loop.size() < 3) continue;
        // The loop runs counter-clockwise about the cut's normal; outward for this side's piece is
        // away from its own material, toward the other side.
        if (side * cp.orient > 0) std::reverse(loop.begin(), loop.end());
        for (size_t k = 0; k < loop.size(); ++k) fan_edges.emplace_back(loop[k], loop[(k + 1) % loop.size()]);
        close_polygon(w, s, e, side, loop, centre);
    }
    front_seams(w, s, c, fan_edges, edge_points, cp.point_edge);
}

}  // namespace

std::array<int64_t, 3> surface_place(const Vec3& x) {
    return {std::llround(x.x() / kQuantum), std::llround(x.y() / kQuantum), std::llround(x.z() / kQuantum)};
}

CutPlaneInfo cut_plane_info(const World& w, int c) {
    CutPlaneInfo cp;
    for (int k = 0; k < 4; ++k)
        if (w.cuts.point_edge[c][k] >= 0) {
            cp.points.push_back(w.cuts.points[c][k]);
            cp.point_edge.push_back(w.cuts.point_edge[c][k]);
        }
    keep_off_skin_vertices(w, w.cuts.element[c], cp);
    return cp;
}

void cut_surface(World& w, SurfaceMesh& s, int first_cut) {
    // Elements whose pieces change: the new cut elements and, around each of their crossed edges,
    // the cut ones (a seam toward a newly cut neighbour goes; points on an edge that has just opened
    // are bound anew) and the whole ones showing skin (a new crack-front point splits it).
    std::vector<int> touched;
    for (int c = first_cut; c < w.cuts.count(); ++c) {
        const int e = w.cuts.element[c];
        touched.push_back(e);
        for (int k = 0; k < 4; ++k) {
            if (w.cuts.point_edge[c][k] < 0) continue;
            const int* ed = local_edge(w, w.cuts.point_edge[c][k]);
            const std::array<int, 4> ends = {w.elements.nodes[e][ed[0]], w.elements.nodes[e][ed[1]], 0, 0};
            for_elements_around(w, ends[0], ends[1], [&](int f) {
                if (is_cut(w, f) || !s.base_of[f].empty()) touched.push_back(f);
            });
        }
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    remove_pieces(s, touched);
    for (int e : touched) {
        if (is_cut(w, e)) cut_element_pieces(w, s, w.cuts.cut_of_element[e]);
        else whole_element_pieces(w, s, e);
    }
}

}  // namespace xcut
