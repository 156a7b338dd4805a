// The sheet of a 2D element cut more than once (systems/cut/recut.h; docs/xfem.md, Several cuts
// per element): each fragment shows the part of its element's skin triangles inside it, the
// triangles clipped by the lines that bound it (Sutherland-Hodgman) and fanned. A point is one
// vertex for every piece whose material is the same there: the same copy (DOF node) of each mesh
// node it is weighted on, however the piece's element was cut. So the lips of a further cut meet
// where material still joins them (a whole element holds the edge) and part where it does not.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"
#include "systems/surface/surface_cut_parts.h"
#include "systems/xfem_queries.h"

namespace xcut::surface_cut_detail {
namespace {

/// The material a binding has at a point: (mesh node, DOF node) of each node it is weighted on,
/// sorted; (-1, -1) past them.
using Signature = std::array<std::pair<int, int>, 3>;

Signature signature(const World& w, int fe, const Eigen::Vector4d& b) {
    Signature sig;
    sig.fill({-1, -1});
    int n = 0;
    for (int a = 0; a < w.elements.nodes_per_element() && n < 3; ++a) {
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
std::vector<Vec3> clean(std::vector<Vec3> poly, double tiny) {
    bool changed = true;
    while (changed && poly.size() >= 3) {
        changed = false;
        for (size_t k = 0; k < poly.size() && !changed; ++k) {
            const Vec3 &p = poly[(k + poly.size() - 1) % poly.size()], &q = poly[k], &r = poly[(k + 1) % poly.size()];
            const Vec3 a = q - p, b = r - q;
            const double cross = a.x() * b.y() - a.y() * b.x();
            if ((q - p).norm() < tiny || std::abs(cross) < tiny * std::max(a.norm(), b.norm()))
                poly.erase(poly.begin() + static_cast<long>(k)), changed = true;
        }
    }
    return poly;
}

}  // namespace

int shared_point(World& w, SurfaceMesh& s, int fe, int8_t side, const Eigen::Vector4d& b, const Vec3& rest) {
    const Signature mine = signature(w, fe, b);
    const std::array<int64_t, 3> place = surface_place(rest);
    if (const auto base = s.base_vertex_at.find(place);
        base != s.base_vertex_at.end() && signature(w, s.element[base->second], s.bary[base->second]) == mine)
        return base->second;
    for (auto [it, end] = s.point_at.equal_range(place); it != end; ++it)
        if (signature(w, s.element[it->second], s.bary[it->second]) == mine) return it->second;
    const int v = s.vertex_count();
    s.position.push_back(rest);
    s.element.push_back(fe);
    s.bary.push_back(b);
    s.side.push_back(side);
    s.point_at.emplace(place, v);
    return v;
}

void fragment_pieces(World& w, SurfaceMesh& s, int c) {
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

namespace xcut::surface_cut_detail {

std::vector<FrontPoint> further_front_points(World& w, SurfaceMesh& s, int e) {
    std::vector<FrontPoint> out;
    const auto& en = w.elements.nodes[e];
    for (int k = 0; k < 3; ++k) {
        const int i = kTriEdges[k][0], j = kTriEdges[k][1];
        const Vec3 &Xi = w.nodes.rest[en[i]], &Xj = w.nodes.rest[en[j]];
        for_elements_around(w, en[i], en[j], [&](int f) {
            const int c = w.cuts.cut_of_element[f];
            if (f == e || c < 0 || w.cuts.lines[c].size() < 2) return;
            const auto& lines = w.cuts.lines[c];
            for (size_t l = 1; l < lines.size(); ++l) {  // the lines after the first (whose points crack_edge_param gives)
                const double di = lines[l].normal.dot(Xi - lines[l].origin), dj = lines[l].normal.dot(Xj - lines[l].origin);
                if ((di > 0.0) == (dj > 0.0) || di == 0.0 || dj == 0.0) continue;
                const double t = di / (di - dj);
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
