// The sheet of a 2D element cut more than once (systems/cut/recut.h; docs/xfem.md, Several cuts
// per element): each fragment shows the part of its element's skin triangles inside it, the
// triangles clipped by the lines that bound it (Sutherland-Hodgman) and fanned. A point is one
// vertex for every piece whose material is the same there: the same copy (DOF node) of each mesh
// node it is weighted on, however the piece's element was cut. So the lips of a further cut meet
// where material still joins them (a whole element holds the edge) and part where it does not.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "engine/fragment_geometry.h"
#include "systems/surface/surface_cut_parts.h"
#include "systems/xfem_queries.h"

namespace xcut::surface_cut_detail {
namespace {

/// The material a binding has at a point: (mesh node, DOF node) of each node it is weighted on,
/// sorted; (-1, -1) past them.
using Signature = std::array<std::pair<int, int>, 4>;

Signature signature(const World& w, int fe, const Eigen::Vector4d& b) {
    Signature sig;
    sig.fill({-1, -1});
    int n = 0;
    for (int a = 0; a < w.elements.nodes_per_element() && n < 4; ++a) {
        if (std::abs(b[a]) < 1e-12) continue;
        const int dof = w.elements.nodes[fe][a];
        sig[n++] = {mesh_node(w, dof), dof};
    }
    std::sort(sig.begin(), sig.begin() + n);
    return sig;
}

/// Barycentric coordinates of rest point x in triangle X (xy), round-off below 1e-12 dropped.
Eigen::Vector4d bary_in(const std::array<Vec3, 3>& X, const Vec3& x) {
    const Vec3 l = triangle_barycentric(X, x);
    Eigen::Vector4d b(l.x(), l.y(), l.z(), 0.0);
    for (int a = 0; a < 3; ++a)
        if (std::abs(b[a]) < 1e-12) b[a] = 0.0;
    return b / b.sum();
}

/// A fragment's polygon with its vertices closer than `tiny` merged and those on a straight run
/// dropped: a clip through a vertex repeats it, and a fan over it would make triangles without area.
/// In space (`space`: a 3D element's polygons) the turn is the cross product's length.
std::vector<Vec3> clean(std::vector<Vec3> poly, double tiny, bool space = false) {
    bool changed = true;
    while (changed && poly.size() >= 3) {
        changed = false;
        for (size_t k = 0; k < poly.size() && !changed; ++k) {
            const Vec3 &p = poly[(k + poly.size() - 1) % poly.size()], &q = poly[k], &r = poly[(k + 1) % poly.size()];
            const Vec3 a = q - p, b = r - q;
            const double cross = space ? a.cross(b).norm() : a.x() * b.y() - a.y() * b.x();
            if ((q - p).norm() < tiny || std::abs(cross) < tiny * std::max(a.norm(), b.norm()))
                poly.erase(poly.begin() + static_cast<long>(k)), changed = true;
        }
    }
    return poly;
}

}  // namespace

int point_of_material(const World& w, const SurfaceMesh& s, int fe, const Eigen::Vector4d& b, const Vec3& rest) {
    const Signature mine = signature(w, fe, b);
    const std::array<int64_t, 3> place = surface_place(rest);
    if (const auto base = s.base_vertex_at.find(place);
        base != s.base_vertex_at.end() && signature(w, s.element[base->second], s.bary[base->second]) == mine)
        return base->second;
    for (auto [it, end] = s.point_at.equal_range(place); it != end; ++it)
        if (signature(w, s.element[it->second], s.bary[it->second]) == mine) return it->second;
    return -1;
}

void merge_material_twins(const World& w, SurfaceMesh& s) {
    std::map<std::pair<std::array<int64_t, 3>, Signature>, int> first;
    std::vector<int> to(s.vertex_count());
    bool any = false;
    for (int v = 0; v < s.vertex_count(); ++v) {
        to[v] = v;
        if (s.element[v] < w.mesh_elements) continue;
        const auto [it, fresh] = first.emplace(std::make_pair(surface_place(vertex_rest(w, s, v)), signature(w, s.element[v], s.bary[v])), v);
        if (!fresh) to[v] = it->second, any = true;
    }
    if (!any) return;
    for (auto& t : s.triangles)
        for (int& v : t) v = to[v];
}

int shared_point(World& w, SurfaceMesh& s, int fe, int8_t side, const Eigen::Vector4d& b, const Vec3& rest) {
    if (const int v = point_of_material(w, s, fe, b, rest); v >= 0) return v;
    const std::array<int64_t, 3> place = surface_place(rest);
    const int v = s.vertex_count();
    s.position.push_back(rest);
    s.element.push_back(fe);
    s.bary.push_back(b);
    s.side.push_back(side);
    s.point_at.emplace(place, v);
    note_bound(w, s, v);
    return v;
}

namespace {

/// Barycentric coordinates of rest point x in tetrahedron X, round-off below 1e-12 dropped.
Eigen::Vector4d bary_in_tet(const std::array<Vec3, 4>& X, const Vec3& x) {
    Eigen::Vector4d b = tet_barycentric(X, x);
    for (int a = 0; a < 4; ++a)
        if (std::abs(b[a]) < 1e-12) b[a] = 0.0;
    return b / b.sum();
}

/// Inserts into convex polygon `poly` (in space) each of `points` that lies on one of its edges,
/// strictly between its ends (within `tol`), in order along the edge; returns how many.
int insert_on_edges(std::vector<Vec3>& poly, const std::vector<Vec3>& points, double tol) {
    std::vector<Vec3> out;
    int inserted = 0;
    for (size_t k = 0; k < poly.size(); ++k) {
        const Vec3 &a = poly[k], &b = poly[(k + 1) % poly.size()];
        out.push_back(a);
        const Vec3 d = b - a;
        const double len2 = d.squaredNorm();
        std::vector<std::pair<double, Vec3>> on;
        for (const Vec3& p : points) {
            const double t = len2 > 0.0 ? (p - a).dot(d) / len2 : 0.0;
            if ((a + t * d - p).norm() <= tol && (p - a).norm() > tol && (p - b).norm() > tol && t > 0.0 && t < 1.0)
                on.push_back({t, p});
        }
        std::sort(on.begin(), on.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
        for (size_t q = 0; q < on.size(); ++q)
            if (q == 0 || (on[q].second - on[q - 1].second).norm() > tol) out.push_back(on[q].second), ++inserted;
    }
    poly = std::move(out);
    return inserted;
}

/// Whether fragment v of cut c is one material with the fragment across its face `poly` on plane
/// `plane` (the same copy of every node: node copies joined them round the end of an incision
/// beside it), so no wound parts them there and neither shows a face on it. The fragment across is
/// the one holding the face's centre moved off the plane by `off` [m]: it may be bounded by fewer
/// planes than v (one that ends before it), so its mask is not v's with one side flipped.
bool joined_across(const World& w, int c, int v, int plane, const std::vector<Vec3>& poly, double off) {
    const VirtualElements& ve = w.virtual_elements;
    const auto& lines = w.cuts.lines[c];
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : poly) centre += p;
    centre /= static_cast<double>(poly.size());
    const double toward = (ve.mask[v] >> plane & 1u) ? -1.0 : 1.0;  // v's side is the other
    const Vec3 across = centre + toward * off * lines[plane].normal.normalized();
    const auto& mine = w.elements.nodes[ve.element[v]];
    for (int u : fragments_of(w, c))
        if (u != v && in_fragment(lines.data(), static_cast<int>(lines.size()), ve.mask[u], across))
            return std::equal(mine.begin(), mine.begin() + 4, w.elements.nodes[ve.element[u]].begin());
    return false;
}

/// Polygon `poly` of a fragment of element e (`material`: its force element and side) as e's
/// pieces, its points `ids` (poly's, snapped: one may have become its neighbour, so repeats are
/// dropped, and fewer than three show nothing): fanned from its first point, or from its centre
/// where a point was inserted on an edge (`inserted`) or the fan would have a flat triangle.
void add_fan(World& w, SurfaceMesh& s, int e, std::pair<int, int8_t> material, const std::vector<Vec3>& poly,
             const std::vector<int>& snapped, bool inserted, bool cut, double tiny) {
    std::vector<int> ids;
    for (const int id : snapped)
        if (ids.empty() || id != ids.back()) ids.push_back(id);
    if (ids.size() > 1 && ids.front() == ids.back()) ids.pop_back();
    if (ids.size() < 3) return;
    std::vector<Vec3> at;  // where its points are, snapped
    for (const int id : ids) at.push_back(vertex_rest(w, s, id));
    // A point taken for the crack's or a neighbour's (snap_to_crack, snap_to_traces, shared_point)
    // may lie on the line of two others: a fan from the first with a flat triangle is fanned from
    // the centre instead.
    for (size_t k = 1; k + 1 < at.size() && !inserted; ++k) {
        const Vec3 a = at[k] - at[0], b = at[k + 1] - at[0];
        inserted = a.cross(b).norm() <= tiny * std::max({a.norm(), b.norm(), (b - a).norm()});
    }
    if (!inserted) {
        for (size_t k = 1; k + 1 < ids.size(); ++k) add_piece(s, {ids[0], ids[k], ids[k + 1]}, e, cut);
        return;
    }
    // The centre of the snapped points, itself not snapped (it is inside); where they are on one
    // line (points snapped onto a trace), the polygon's own centre, off it: its triangles join the
    // line's points on either side.
    double longest = 0.0;
    for (size_t k = 0; k < at.size(); ++k) longest = std::max(longest, (at[(k + 1) % at.size()] - at[k]).norm());
    const bool flat = 2.0 * polygon_area_3d(at) <= 1e-9 * longest * longest;
    Vec3 centre = Vec3::Zero();
    for (const Vec3& x : flat ? poly : at) centre += x;
    centre /= static_cast<double>(flat ? poly.size() : at.size());
    const int mid = shared_point(w, s, material.first, material.second, bary_in_tet(rest_corners(w, e), centre), centre);
    for (size_t k = 0; k < ids.size(); ++k) add_piece(s, {mid, ids[k], ids[(k + 1) % ids.size()]}, e, cut);
}

/// A skin corner exactly where a plane crosses a mesh edge (poly[k], of fragment v of cut c, in
/// `cut`: a wound face) is shown as the elements cut once round it show it (corner_on_crossing):
/// there the corner stays on the side of the edge's lower-numbered node and the crossing lies just
/// past it, one copy per side. So a wound face and the skin of the fragment past the corner take
/// the crossing instead of it; the skin of the fragment on the corner's side takes the corner
/// (`point`), and the crossing after it where its rim leaves the corner along a plane through it
/// (the wound's rim starts there). Appends the points to `ids`; false (nothing appended) elsewhere.
/// X: the element's rest corners; tiny [m]: fragment_pieces_3d's tolerance of a point on a plane.
template <class Point>
bool corner_ids(World& w, SurfaceMesh& s, int c, int v, const std::array<Vec3, 4>& X, double tiny, const std::vector<Vec3>& poly,
                size_t k, bool cut, const Point& point, std::vector<int>& ids) {
    const int e = w.cuts.element[c];
    const Vec3& p = poly[k];
    Eigen::Vector4d at;
    int kept = -1;
    if (!s.base_vertex_at.contains(surface_place(p)) || !corner_on_crossing(w, e, bary_in_tet(X, p), at, kept)) return false;
    const auto& lines = w.cuts.lines[c];
    const int nl = static_cast<int>(lines.size());
    const VirtualElements& ve = w.virtual_elements;
    const int moved = shared_point(w, s, ve.element[v], ve.side[v], at, rest_of(w, e, at));
    if (cut || !in_fragment(lines.data(), nl, ve.mask[v], p + 1e-3 * (X[kept] - p))) {
        ids.push_back(moved);
        return true;
    }
    const auto on_plane = [&](const Vec3& q) {  // p -> q along a plane of the cut
        for (const CutLine& l : lines)
            if (std::abs((p - l.origin).dot(l.normal)) <= tiny && std::abs((q - l.origin).dot(l.normal)) <= tiny) return true;
        return false;
    };
    ids.push_back(point(p));
    const size_t m = poly.size();
    if (on_plane(poly[(k + 1) % m])) ids.push_back(moved);
    else if (on_plane(poly[(k + m - 1) % m])) ids.insert(ids.end() - 1, moved);
    return true;
}

/// Cut element c's pieces in 3D (c having planes): per fragment, its element's skin triangles
/// clipped to it, and its faces on its cut planes (the wound, oriented out of the fragment) with
/// the skin's crossings on their rims inserted, fanned from their centre where any was (so no
/// triangle is without area and the skin meets the wound without a T-junction).
void fragment_pieces_3d(World& w, SurfaceMesh& s, int c) {
    const int e = w.cuts.element[c];
    const auto& n = w.elements.nodes[e];
    const std::array<Vec3, 4> X = rest_corners(w, e);
    double size = 0.0;
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) size = std::max(size, (X[b] - X[a]).norm());
    const double tiny = std::max(1e-9 * size, 2e-11);  // and never two points at one place (1e-11 m)
    const auto& lines = w.cuts.lines[c];
    const int nl = static_cast<int>(lines.size());
    const VirtualElements& ve = w.virtual_elements;
    // The points other cuts make on a polygon's edges: where the planes of the elements cut again
    // across its faces and edges cross them, and a crack's point on a mesh edge it runs along.
    const auto others_on = [&](const std::vector<Vec3>& poly) {
        std::vector<Vec3> out;
        for (size_t k = 0; k < poly.size(); ++k) {
            const Vec3 &a = poly[k], &b = poly[(k + 1) % poly.size()];
            const Eigen::Vector4d ba = bary_in_tet(X, a), bb = bary_in_tet(X, b);
            for (const auto& [t, x] : further_crossings(w, e, a, b, ba, bb)) out.push_back(x);
            std::array<int, 4> on{};  // the nodes either end weighs: two, a mesh edge
            int m = 0;
            for (int q = 0; q < 4; ++q)
                if (ba[q] != 0.0 || bb[q] != 0.0) on[m++] = q;
            if (m != 2) continue;
            for (const double t : edge_crossings(w, n[on[0]], n[on[1]])) out.push_back(rest_of(w, e, on_edge(on[0], on[1], t)));
        }
        return out;
    };
    for (int v : fragments_of(w, c)) {
        const int fe = ve.element[v];
        const auto point = [&](const Vec3& p) {
            Eigen::Vector4d b = bary_in_tet(X, p);
            if (!s.base_vertex_at.contains(surface_place(p))) snap_to_crack(w, e, b), snap_to_traces(w, e, size, b);  // a skin corner stays
            return shared_point(w, s, fe, ve.side[v], b, rest_of(w, e, b));
        };
        // A polygon with the points `extra` on its edges inserted, fanned from its first vertex, or
        // from its centre where a point was inserted (so no triangle is without area).
        const auto add_polygon = [&](std::vector<Vec3> poly, std::vector<Vec3> extra, bool cut) {
            const std::vector<Vec3> others = others_on(poly);
            extra.insert(extra.end(), others.begin(), others.end());
            bool inserted = insert_on_edges(poly, extra, tiny) > 0;
            std::vector<int> ids;
            for (size_t k = 0; k < poly.size(); ++k) {
                const size_t before = ids.size();
                if (!corner_ids(w, s, c, v, X, tiny, poly, k, cut, point, ids)) ids.push_back(point(poly[k]));
                inserted = inserted || ids.size() > before + 1;
            }
            add_fan(w, s, e, {fe, ve.side[v]}, poly, ids, inserted, cut, tiny);
        };
        std::vector<Vec3> skin;  // the clipped skin's points: the rims of the cut faces pass through them
        for (int bt : s.base_of[e]) {
            const auto& tri = s.base_triangles[bt];
            std::vector<Vec3> poly{vertex_rest(w, s, tri[0]), vertex_rest(w, s, tri[1]), vertex_rest(w, s, tri[2])};
            poly = clean(clip_by_planes(std::move(poly), lines.data(), nl, ve.mask[v]), tiny, true);
            if (poly.size() < 3) continue;
            skin.insert(skin.end(), poly.begin(), poly.end());
            add_polygon(std::move(poly), {}, false);
        }
        for (const FragmentFace& f : fragment_faces(X, lines.data(), nl, ve.mask[v])) {
            std::vector<Vec3> poly = clean(f.polygon, tiny, true);
            if (f.plane >= 0 && poly.size() >= 3 && !joined_across(w, c, v, f.plane, poly, 1e-6 * size)) add_polygon(std::move(poly), skin, true);
        }
    }
}

}  // namespace

void fragment_pieces(World& w, SurfaceMesh& s, int c) {
    if (w.elements.dim == 3) {
        fragment_pieces_3d(w, s, c);
        return;
    }
    const int e = w.cuts.element[c];
    const auto& n = w.elements.nodes[e];
    const std::array<Vec3, 3> X{w.nodes.rest[n[0]], w.nodes.rest[n[1]], w.nodes.rest[n[2]]};
    const auto& lines = w.cuts.lines[c];
    const VirtualElements& ve = w.virtual_elements;
    for (int bt : s.base_of[e]) {
        const auto& tri = s.base_triangles[bt];
        std::vector<Vec3> corner(3);
        double size = 0.0;
        for (int k = 0; k < 3; ++k) corner[k] = vertex_rest(w, s, tri[k]);
        for (int k = 0; k < 3; ++k) size = std::max(size, (corner[(k + 1) % 3] - corner[k]).norm());
        for (int v : fragments_of(w, c)) {
            std::vector<Vec3> poly = corner;
            for (int k = 0; k < static_cast<int>(lines.size()) && poly.size() >= 3; ++k)
                if (ve.mask[v] & bound_by(k)) poly = clip_to_side(poly, lines[k], ve.mask[v] >> k & 1u);
            poly = clean(poly, std::max(1e-9 * size, 2e-11));  // and never two points at one place (1e-11 m)
            if (poly.size() < 3) continue;
            const int fe = ve.element[v];
            std::vector<int> ids;
            for (const Vec3& p : poly) {
                const Eigen::Vector4d b = bary_in(X, p);
                int id = -1;
                for (int k = 0; k < 3 && id < 0; ++k)  // a corner of the skin triangle, if its material is this one's
                    if (p == corner[k] && signature(w, s.element[tri[k]], s.bary[tri[k]]) == signature(w, fe, b)) id = tri[k];
                ids.push_back(id >= 0 ? id : shared_point(w, s, fe, ve.side[v], b, p));
            }
            for (size_t k = 1; k + 1 < ids.size(); ++k) add_piece(s, {ids[0], ids[k], ids[k + 1]}, e, false);
        }
    }
}

}  // namespace xcut::surface_cut_detail

namespace xcut {

void bind_to_fragments(World& w, SurfaceMesh& s, int c) {
    using namespace surface_cut_detail;
    const int e = w.cuts.element[c];
    const std::span<const int> frags = fragments_of(w, c);
    for (int u : s.bound_to[e]) {
        if (mesh_element_of(w, s.element[u]) != e) continue;  // bound elsewhere since
        const Vec3 x = rest_of(w, e, local_bary(w, s, e, u));
        for (int v : frags)
            if (in_fragment(w.cuts.lines[c].data(), static_cast<int>(w.cuts.lines[c].size()), w.virtual_elements.mask[v], x)) {
                s.bary[u] = local_bary(w, s, e, u);
                s.element[u] = w.virtual_elements.element[v];
                s.side[u] = w.virtual_elements.side[v];
                break;
            }
    }
}

}  // namespace xcut
