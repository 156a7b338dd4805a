// Where cuts cross the mesh's edges and faces, for the surfaces of elements cut again in 3D
// (docs/xfem.md, Scalpels in 3D: several incisions at one place): a plane's crossing of an edge
// and its trace on a face are where the cut's own points put them (CutElements::line_edge_t),
// the same in every element round them, though the planes fitted through those points at rest
// miss them by micrometres; the surfaces' points snap onto them, and a whole or cut-once element
// shows where further planes of its neighbours end on its edges and faces.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"
#include "systems/surface/surface_cut_parts.h"
#include "systems/xfem_queries.h"

namespace xcut::surface_cut_detail {
namespace {

/// How far cut element c's planes cross its edges (rest corners X) from the points they were made
/// through, at most, as a fraction of the edge [-]: a cut's four points that its neighbours all
/// fixed before (systems/cut/recut.h: join_earlier_points) need not lie on one plane.
double plane_misfit(const World& w, int c, const std::array<Vec3, 4>& X) {
    const auto& lines = w.cuts.lines[c];
    double worst = 0.0;
    for (size_t l = 0; l < lines.size() && l < w.cuts.line_edge_t[c].size(); ++l)
        for (int k = 0; k < 6; ++k) {
            const double t = w.cuts.line_edge_t[c][l][k];
            const Vec3 &a = X[kTetEdges[k][0]], &b = X[kTetEdges[k][1]];
            const double da = lines[l].normal.dot(a - lines[l].origin), db = lines[l].normal.dot(b - lines[l].origin);
            if (t >= 0.0 && da != db) worst = std::max(worst, std::abs(da / (da - db) - t));
        }
    return worst;
}

/// The trace of line l of cut c (element e, 3D) on e's face opposite local node o: the segment
/// between its two crossings of the face's edges where the cut's own points put them
/// (CutElements::line_edge_t; a cut once: its points), each end made from the edge's
/// lower-numbered node, so the element across the face, cut by the same incision, makes the same
/// segment. False if it has no trace there.
bool face_trace(const World& w, int e, int c, size_t l, int o, std::array<Vec3, 2>& ends) {
    if (l >= std::max<size_t>(1, w.cuts.lines[c].size())) return false;
    const std::array<double, 6> edge_t = line_edge_params(w, c, l);
    const auto& en = w.elements.nodes[e];
    int m = 0;
    for (int k = 0; k < 6; ++k) {
        const int i = kTetEdges[k][0], j = kTetEdges[k][1];
        double t = edge_t[k];
        if (i == o || j == o || !(t > 0.0 && t < 1.0)) continue;
        if (m == 2) return false;
        const int lo = std::min(en[i], en[j]), hi = std::max(en[i], en[j]);
        if (en[i] != lo) t = 1.0 - t;
        ends[m++] = w.nodes.rest[lo] + t * (w.nodes.rest[hi] - w.nodes.rest[lo]);
    }
    if (m == 2 && std::lexicographical_compare(ends[1].data(), ends[1].data() + 3, ends[0].data(), ends[0].data() + 3))
        std::swap(ends[0], ends[1]);
    return m == 2;
}

/// Where line l of cut c (of element f; 3D) crosses mesh edge na -> nb, as a parameter from na:
/// the cut's own point there (CutElements::line_edge_t), which the fragments' polygons take for
/// the plane's crossing (snap_to_crack), or, where it records none, the plane's crossing; -1 where
/// the plane does not cross the edge.
double line_crossing(const World& w, int f, int c, size_t l, int na, int nb) {
    bool from_a = true;
    const int k = w.elements.dim == 3 && l < w.cuts.line_edge_t[c].size() ? local_edge_of(w, f, na, nb, from_a) : -1;
    if (k >= 0 && w.cuts.line_edge_t[c][l][k] >= 0.0) return param_from(w.cuts.line_edge_t[c][l][k], from_a);
    const CutLine& line = w.cuts.lines[c][l];
    const double da = line.normal.dot(w.nodes.rest[na] - line.origin), db = line.normal.dot(w.nodes.rest[nb] - line.origin);
    return (da > 0.0) == (db > 0.0) || da == 0.0 || db == 0.0 ? -1.0 : da / (da - db);
}

/// The local node of element f opposite its face through mesh nodes on[0..2].
int face_opposite(const World& w, int f, const std::array<int, 3>& on) {
    for (int a = 0; a < 4; ++a)
        if (std::find(on.begin(), on.end(), w.elements.nodes[f][a]) == on.end()) return a;
    return -1;
}

/// Where segment a -> b crosses the line of trace `ends` (both in one face), as a parameter from a
/// more than 1e-9 from either end; -1 where they are parallel or cross elsewhere.
double trace_crossing(const Vec3& a, const Vec3& b, const std::array<Vec3, 2>& ends) {
    const Vec3 d1 = b - a, d2 = ends[1] - ends[0], n = d1.cross(d2);
    if (n.squaredNorm() < 1e-12 * d1.squaredNorm() * d2.squaredNorm()) return -1.0;
    const double t = (ends[0] - a).cross(d2).dot(n) / n.squaredNorm();
    return t > 1e-9 && t < 1.0 - 1e-9 ? t : -1.0;
}

}  // namespace

/// The rest corners of tetrahedron e.
std::array<Vec3, 4> rest_corners(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {w.nodes.rest[n[0]], w.nodes.rest[n[1]], w.nodes.rest[n[2]], w.nodes.rest[n[3]]};
}

namespace {

/// Whether barycentric b (a tetrahedron's) weighs exactly two nodes, local i < j: a point on that
/// mesh edge.
bool on_mesh_edge(const Eigen::Vector4d& b, int& i, int& j) {
    std::array<int, 4> on{};
    int n = 0;
    for (int a = 0; a < 4; ++a)
        if (b[a] != 0.0) on[n++] = a;
    if (n != 2) return false;
    i = on[0], j = on[1];
    return true;
}

}  // namespace

/// A point on a mesh edge of element e (barycentric b, two weights) within 1e-4 of the edge (or
/// 1.5 x the planes' misfit of the elements round it: plane_misfit) from where the crack crosses
/// it as the surface places that crossing (edge_crossing) is that point: a plane fitted through a
/// cut's points made on the moved tissue misses the fourth by a few micrometres at rest, and the
/// neighbours' lips use the points themselves.
void snap_to_crack(const World& w, int e, Eigen::Vector4d& b) {
    int i = -1, j = -1;
    if (!on_mesh_edge(b, i, j)) return;
    const auto& en = w.elements.nodes[e];
    double t = -1.0;  // the crossing nearest b, from en[i]
    for (const double u : edge_crossings(w, en[i], en[j]))
        if (t < 0.0 || std::abs(u - b[j]) < std::abs(t - b[j])) t = u;
    double within = 1e-4;  // of the edge, or 1.5 x the worst misfit of the planes of the elements round it
    for_elements_around(w, en[i], en[j], [&](int f) {
        const int c = w.cuts.cut_of_element[f];
        if (c >= 0 && !w.cuts.lines[c].empty()) within = std::max(within, 1.5 * plane_misfit(w, c, rest_corners(w, f)));
    });
    if (t > 0.0 && t < 1.0 && std::abs(t - b[j]) < within) b = on_edge(i, j, t);
}

bool corner_on_crossing(const World& w, int e, const Eigen::Vector4d& b, Eigen::Vector4d& crossing, int& kept) {
    int i = -1, j = -1;
    if (!on_mesh_edge(b, i, j)) return false;
    const auto& en = w.elements.nodes[e];
    const double moved = surface_edge_param(en[i], en[j], b[j]);
    if (moved == b[j]) return false;
    for (const double t : edge_crossings(w, en[i], en[j]))
        if (std::abs(t - moved) <= 1e-12) {
            crossing = on_edge(i, j, t);
            kept = en[i] < en[j] ? i : j;  // moved toward the higher-numbered node: the corner is the other's side
            return true;
        }
    return false;
}

/// A point on a face of element e (barycentric b, one weight zero) near the traces of two planes
/// there (face_trace; the planes of e's cut and of the element across the face, each trace once;
/// within 1e-4 of `size` [m], or 1.5 times the misfit of the element's planes: plane_misfit) is
/// where those traces cross (or the point of an edge where both end: two incisions' points joined
/// there): the planes fitted through the cuts' points at rest miss them by micrometres, and
/// differently in the two elements, whose wounds must meet at the same point.
void snap_to_traces(const World& w, int e, double size, Eigen::Vector4d& b) {
    int o = -1, zeros = 0;
    for (int a = 0; a < 4; ++a)
        if (b[a] == 0.0) o = a, ++zeros;
    if (zeros != 1) return;
    const Vec3 p = rest_of(w, e, b);
    // The two elements of the face (f, its face opposite local node of) and the cuts with planes.
    std::array<std::array<int, 2>, 2> sides{{{e, o}, {element_across(w, e, o), -1}}};
    for (int a = 0; a < 4 && sides[1][0] >= 0; ++a)
        if (!holds(w, e, w.elements.nodes[sides[1][0]][a])) sides[1][1] = a;
    double within = 0.0;  // [m]
    for (auto& [f, of] : sides) {
        const int c = f < 0 ? -1 : w.cuts.cut_of_element[f];
        if (c < 0) f = -1;
        else within = std::max(within, std::max(1e-4, 1.5 * plane_misfit(w, c, rest_corners(w, f))) * size);
    }
    std::vector<std::array<Vec3, 2>> near;
    for (const auto& [f, of] : sides)
        for (size_t l = 0; f >= 0 && l < std::max<size_t>(1, w.cuts.lines[w.cuts.cut_of_element[f]].size()); ++l) {
            std::array<Vec3, 2> ends;
            if (!face_trace(w, f, w.cuts.cut_of_element[f], l, of, ends)) continue;
            const Vec3 d = ends[1] - ends[0];
            const double u = std::clamp((p - ends[0]).dot(d) / d.squaredNorm(), 0.0, 1.0);
            const bool known = std::any_of(near.begin(), near.end(), [&](const auto& s) { return (s[0] - ends[0]).norm() < 1e-12 * size && (s[1] - ends[1]).norm() < 1e-12 * size; });
            if (!known && (ends[0] + u * d - p).norm() < within) near.push_back(ends);
        }
    const auto snap = [&](const Vec3& x) {
        b = tet_barycentric(rest_corners(w, e), x);
        b[o] = 0.0;
        for (int a = 0; a < 4; ++a)
            if (std::abs(b[a]) < 1e-12) b[a] = 0.0;
        b /= b.sum();
    };
    // A point within `within` of two traces crossing at angle a lies within within / sin a of
    // where they cross; sin a is taken at least 0.5 (twice `within` at most: a point of a polygon
    // near a crossing of traces at a small angle is not always that crossing).
    const auto reach = [&](const std::array<Vec3, 2>& s1, const std::array<Vec3, 2>& s2) {
        const Vec3 d1 = s1[1] - s1[0], d2 = s2[1] - s2[0];
        return within / std::max(0.5, d1.cross(d2).norm() / (d1.norm() * d2.norm()));
    };
    if (near.size() != 2) return;
    // Traces that end at one point of an edge (incisions' points joined there) cross there.
    for (const Vec3& x : near[0])
        if (((x - near[1][0]).norm() < 1e-12 * size || (x - near[1][1]).norm() < 1e-12 * size) && (x - p).norm() < reach(near[0], near[1])) {
            snap(x);
            return;
        }
    const auto key = [](const std::array<Vec3, 2>& s) { return std::array<double, 6>{s[0].x(), s[0].y(), s[0].z(), s[1].x(), s[1].y(), s[1].z()}; };
    if (key(near[1]) < key(near[0])) std::swap(near[0], near[1]);
    const Vec3 d1 = near[0][1] - near[0][0], d2 = near[1][1] - near[1][0], r = near[1][0] - near[0][0];
    const Vec3 n = d1.cross(d2);
    if (n.squaredNorm() < 1e-6 * d1.squaredNorm() * d2.squaredNorm()) return;  // nearly parallel: no one point
    const double u = r.cross(d2).dot(n) / n.squaredNorm();
    if (!(u > 0.0 && u < 1.0)) return;
    const Vec3 x = near[0][0] + u * d1;
    if ((x - p).norm() < reach(near[0], near[1])) snap(x);
}

std::vector<std::pair<double, Vec3>> further_crossings(const World& w, int e, const Vec3& a, const Vec3& b,
                                                       const Eigen::Vector4d& ba, const Eigen::Vector4d& bb) {
    std::vector<std::pair<double, Vec3>> out;
    // The nodes both ends have no weight on: one, the face opposite it; two, the edge between
    // the other two (every element round it).
    std::array<int, 4> off{};
    int n_off = 0;
    for (int k = 0; k < 4; ++k)
        if (std::abs(ba[k]) < 1e-12 && std::abs(bb[k]) < 1e-12) off[n_off++] = k;
    if (n_off == 0 || n_off > 2 || w.elements.dim != 3) return out;
    const auto& en = w.elements.nodes[e];
    std::array<int, 3> on{};
    for (int k = 0, m = 0; k < 4; ++k)
        if (std::find(off.begin(), off.begin() + n_off, k) == off.begin() + n_off) on[m++] = en[k];
    const double tiny = 1e-9 * (b - a).norm();
    for_elements_around(w, on[0], on[1], [&](int f) {
        const int c = f == e ? -1 : w.cuts.cut_of_element[f];
        if (c < 0 || (n_off == 1 && !holds(w, f, on[2])) || w.cuts.lines[c].empty()) return;
        const auto& lines = w.cuts.lines[c];
        for (size_t l = 0; l < lines.size(); ++l) {
            const double da = lines[l].normal.dot(a - lines[l].origin), db = lines[l].normal.dot(b - lines[l].origin);
            if (!((da > tiny && db < -tiny) || (da < -tiny && db > tiny))) continue;
            double t = da / (da - db);
            if (n_off == 2) {  // along the mesh edge on[0] -> on[1]: the cut's own point there, as the surface places it
                const Vec3 &X0 = w.nodes.rest[on[0]], &X1 = w.nodes.rest[on[1]];
                const double u = surface_edge_param(on[0], on[1], line_crossing(w, f, c, l, on[0], on[1]));
                const double along = (X0 + u * (X1 - X0) - a).dot(b - a) / (b - a).squaredNorm();
                if (u > 0.0 && u < 1.0 && along > 0.0 && along < 1.0) t = along;
            } else if (std::array<Vec3, 2> ends; face_trace(w, f, c, l, face_opposite(w, f, on), ends)) {
                t = trace_crossing(a, b, ends);  // in the face: where the plane's recorded trace crosses
                if (t < 0.0) continue;  // it ends at an end of the segment (two incisions' points joined)
            }
            const Vec3 x = a + t * (b - a);
            bool bounds = false;  // the plane parts fragments there
            for (int v : fragments_of(w, c))
                bounds = bounds || ((w.virtual_elements.mask[v] & bound_by(static_cast<int>(l))) &&
                                    in_fragment(lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v], x));
            if (bounds) out.push_back({t, x});
        }
    });
    std::sort(out.begin(), out.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
    return out;
}

void split_at_further_points(World& w, SurfaceMesh& s, int c, const CutPlaneInfo& cp) {
    const int e = w.cuts.element[c];
    const auto& en = w.elements.nodes[e];
    for (int k = 0; k < 6; ++k) {
        const int i = kTetEdges[k][0], j = kTetEdges[k][1];
        const Vec3 &Xi = w.nodes.rest[en[i]], &Xj = w.nodes.rest[en[j]];
        const double tol = 1e-9 * (Xj - Xi).norm();
        // The planes of elements cut again, and other incisions' crossings of the edge (its own
        // is a vertex of its pieces already, and passed over below).
        std::vector<std::pair<double, Vec3>> points = further_crossings(w, e, Xi, Xj, on_edge(i, j, 0.0), on_edge(i, j, 1.0));
        if (several_per_edge(w))
            for (const double t : edge_crossings(w, en[i], en[j])) points.push_back({t, Xi + t * (Xj - Xi)});
        for (const auto& [t, x] : points) {
            const Eigen::Vector4d b = on_edge(i, j, t);
            const int side = side_of_cut(w, cp, e, b);
            const int fe = w.virtual_elements.element[w.cuts.virtual_element[c][side > 0 ? 0 : 1]];
            int id = -1;
            const std::vector<int> pieces = s.pieces_of[e];
            for (int p : pieces) {
                if (s.cut_face[p]) continue;
                const std::array<int, 3> tri = s.triangles[p];
                for (int q = 0; q < 3; ++q) {
                    const Vec3 a = vertex_rest(w, s, tri[q]), d = vertex_rest(w, s, tri[(q + 1) % 3]) - a;
                    const double u = (x - a).dot(d) / d.squaredNorm();
                    if ((a + u * d - x).norm() > tol || (x - a).norm() <= tol || (a + d - x).norm() <= tol || u <= 0.0 || u >= 1.0)
                        continue;
                    if (id < 0) id = shared_point(w, s, fe, static_cast<int8_t>(side), b, x);
                    s.triangles[p] = {tri[q], id, tri[(q + 2) % 3]};
                    add_piece(s, {id, tri[(q + 1) % 3], tri[(q + 2) % 3]}, e, false);
                    break;
                }
            }
        }
    }
}

std::vector<FrontPoint> further_front_points(World& w, SurfaceMesh& s, int e) {
    std::vector<FrontPoint> out;
    const auto& en = w.elements.nodes[e];
    for (int k = 0; k < edge_count(w); ++k) {
        const int i = local_edge(w, k)[0], j = local_edge(w, k)[1];
        const Vec3 &Xi = w.nodes.rest[en[i]], &Xj = w.nodes.rest[en[j]];
        for_elements_around(w, en[i], en[j], [&](int f) {
            const int c = w.cuts.cut_of_element[f];
            if (f == e || c < 0 || w.cuts.lines[c].size() < 2) return;
            const auto& lines = w.cuts.lines[c];
            for (size_t l = 1; l < lines.size(); ++l) {  // the lines after the first (whose points crack_edge_param gives)
                const double t = line_crossing(w, f, c, l, en[i], en[j]);
                if (!(t > 0.0 && t < 1.0)) continue;
                const Vec3 p = Xi + t * (Xj - Xi);
                bool bounds = false;  // the line parts fragments there (a T's stem ends at its wound)
                for (int v : fragments_of(w, c))
                    bounds = bounds || ((w.virtual_elements.mask[v] & bound_by(static_cast<int>(l))) && in_fragment(lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v], p));
                if (!bounds) continue;
                Eigen::Vector4d b = Eigen::Vector4d::Zero();
                b[i] = 1.0 - t, b[j] = t;
                out.push_back({i, j, shared_point(w, s, e, 0, b, p), t});
            }
        });
    }
    return out;
}

}  // namespace xcut::surface_cut_detail
