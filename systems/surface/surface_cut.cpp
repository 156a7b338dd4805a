// The skin along a cut: each touched element's skin triangles regenerated, split per side in a
// cut element and at the crack-front points in a whole one (paper §3.4, Fig. 6). The points and
// their bindings: surface_points.cpp; the cut face's rim: surface_rim.cpp; the closing faces:
// surface_cut_faces.cpp.
#include "systems/surface/surface_cut.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "systems/surface/surface_cut_parts.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

using namespace surface_cut_detail;

/// A whole element's pieces: its skin triangles, each split at the crack-front points on its
/// edges. Triangle a-b-c with the front point P inside a-b becomes a-P-c and P-b-c: P is one vertex
/// for both lips while this whole element holds its edge (surface_point).
void whole_element_pieces(World& w, SurfaceMesh& s, int e) {
    if (s.base_of[e].empty()) return;
    const auto& en = w.elements.nodes[e];
    std::vector<FrontPoint> front = further_front_points(w, s, e);
    for (int k = 0; k < edge_count(w); ++k) {
        const int i = local_edge(w, k)[0], j = local_edge(w, k)[1];
        const int hi = w.enriched.sign[en[i]] >= 0 ? 1 : -1;
        for (const double t : edge_crossings(w, en[i], en[j])) front.push_back({i, j, surface_point(w, s, e, hi, on_edge(i, j, t)), t});
    }
    std::vector<std::array<int, 3>> pieces;
    for (int bt : s.base_of[e]) {
        pieces.assign(1, s.base_triangles[bt]);
        for (const FrontPoint& p : front)
            for (size_t q = 0; q < pieces.size(); ++q) {
                const auto tri = pieces[q];
                int split = -1;
                for (int k = 0; k < 3 && split < 0; ++k) {
                    const Eigen::Vector4d ba = local_bary(w, s, e, tri[k]), bb = local_bary(w, s, e, tri[(k + 1) % 3]);
                    const bool on_ij = std::abs(ba[p.i] + ba[p.j] - 1.0) < 1e-12 && std::abs(bb[p.i] + bb[p.j] - 1.0) < 1e-12;
                    if (on_ij && (ba[p.j] - p.t) * (bb[p.j] - p.t) < 0.0) split = k;
                }
                if (split < 0) continue;
                const int a = tri[split], b = tri[(split + 1) % 3], c = tri[(split + 2) % 3];
                pieces[q] = {a, p.v, c};
                pieces.push_back({p.v, b, c});
                break;
            }
        for (const auto& t : pieces) add_piece(s, t, e, false);
    }
}

/// A cut element's pieces: its skin triangles split per side, then (3D) the internal mesh: edge
/// points and rim points around the cut, a fan per side.
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
        const bool pinned = x1l == x1m && x2l == x2m;  // both ends on the front
        const int pl = pinned ? parting_point(w, s, e, sl, x1l, x2l, true) : -1;
        if (pl < 0) {
            add_piece(s, {L, x1l, x2l}, e, false);
            add_piece(s, {x1m, M1, M2}, e, false);
            add_piece(s, {x1m, M2, x2m}, e, false);
        } else {  // the incision parts between two front points: x1 -> parting point -> x2 on each side
            const int pm = parting_point(w, s, e, sm, x1m, x2m, true);
            add_piece(s, {L, x1l, pl}, e, false);
            add_piece(s, {L, pl, x2l}, e, false);
            add_piece(s, {pm, x1m, M1}, e, false);
            add_piece(s, {pm, M1, M2}, e, false);
            add_piece(s, {pm, M2, x2m}, e, false);
        }
    }
    if (w.elements.dim == 3) split_at_further_points(w, s, c, cp), cut_faces(w, s, c, cp, rim);  // in 2D the sheet is the surface: the gap is the cut
}

bool has_lines(const World& w, int e) { return is_cut(w, e) && !w.cuts.lines[w.cuts.cut_of_element[e]].empty(); }

/// Makes the pieces of `elements` (sorted, unique) again: the elements cut more than once last, so
/// their points find those the others made (shared_point).
void remake_pieces(World& w, SurfaceMesh& s, const std::vector<int>& elements) {
    remove_pieces(s, elements);
    for (int e : elements) {
        if (has_lines(w, e)) continue;
        if (is_cut(w, e)) cut_element_pieces(w, s, w.cuts.cut_of_element[e]);
        else whole_element_pieces(w, s, e);
    }
    for (int e : elements)
        if (has_lines(w, e)) fragment_pieces(w, s, w.cuts.cut_of_element[e]);
}

/// Where elements are cut again in 3D a cut element's pieces take their points by material
/// (shared_point), so a point bound to a whole element where the lips met there (a crack front's)
/// is never opened when that element is cut: each still bound to an element cut since `first_cut`
/// is listed as opened (SurfaceMesh::opened), so the pieces using it are made again and bind it anew.
void open_points_of_new_cuts(World& w, SurfaceMesh& s, int first_cut) {
    std::vector<uint8_t> fresh(w.mesh_elements, 0);
    for (int c = first_cut; c < w.cuts.count(); ++c) fresh[w.cuts.element[c]] = 1;
    for (int v = 0; v < s.vertex_count(); ++v) {
        const int e = s.element[v];
        if (e < 0 || e >= w.mesh_elements || !fresh[e]) continue;
        int lo = -1, hi = -1;
        for (int a = 0; a < w.elements.nodes_per_element(); ++a) {
            if (s.bary[v][a] == 0.0) continue;
            const int j = w.elements.nodes[e][a];
            lo = lo < 0 ? j : std::min(lo, j), hi = std::max(hi, j);
        }
        if (lo >= 0) s.opened.push_back({v, lo, hi});
        // Bound to the element's first side meanwhile (a pieces' remake binds it where it is used).
        s.element[v] = w.virtual_elements.element[w.cuts.virtual_element[w.cuts.cut_of_element[e]][0]];
    }
}

}  // namespace

int zero_area_triangles(const SurfaceMesh& s) {
    int zero = 0;
    for (const auto& t : s.triangles) {
        const Vec3 a = s.position[t[1]] - s.position[t[0]], b = s.position[t[2]] - s.position[t[0]];
        const double longest = std::max({a.squaredNorm(), b.squaredNorm(), (b - a).squaredNorm()});
        zero += !(a.cross(b).norm() > 1e-12 * longest);
    }
    return zero;
}

void cut_surface(World& w, SurfaceMesh& s, int first_cut, int first_crossing, int first_recut) {
    // Elements whose pieces change: the new cut elements and, around each of their crossed edges,
    // the cut ones (points on an edge that has just opened are bound anew) and the whole ones
    // showing skin (a new crack-front point splits it); around an element with lines (2D), every
    // element at its nodes, whose copies it may have changed.
    std::vector<int> touched;
    std::vector<int> with_lines;
    for (size_t k = first_recut; k < w.cuts.recut_log.size(); ++k) with_lines.push_back(w.cuts.element[w.cuts.recut_log[k]]);
    // Where elements are cut again in 3D the lips meet where the sides hold one copy of a node
    // (lips_joined), so every element at a new cut element's nodes, whose copies it may have
    // parted, is made again too (one whose lips met all round shows no face and uses no point).
    const bool by_copies = w.elements.dim == 3 && recut_allowed(w);
    for (int c = first_cut; c < w.cuts.count(); ++c)
        if (!w.cuts.lines[c].empty() || by_copies) with_lines.push_back(w.cuts.element[c]);
    for (int e : with_lines)
        for (int a = 0; a < w.elements.nodes_per_element(); ++a) {
            const int j = w.elements.nodes[e][a];
            for (int p = w.incidence.offset[j]; p < w.incidence.offset[j + 1]; ++p) touched.push_back(w.incidence.entry[p] >> 2);
        }
    for (int c = first_cut; c < w.cuts.count(); ++c) {
        const int e = w.cuts.element[c];
        touched.push_back(e);
        for (int k = 0; k < 4; ++k) {
            if (w.cuts.point_edge[c][k] < 0) continue;
            const int* ed = local_edge(w, w.cuts.point_edge[c][k]);
            for_elements_around(w, w.elements.nodes[e][ed[0]], w.elements.nodes[e][ed[1]], [&](int f) {
                if (is_cut(w, f) || !s.base_of[f].empty()) touched.push_back(f);
            });
        }
    }
    const auto& log = w.cuts.crossed_log;
    for (size_t k = first_crossing; k < log.size(); ++k)
        for_elements_around(w, log[k][0], log[k][1], [&](int f) {
            if (is_cut(w, f) || !s.base_of[f].empty()) touched.push_back(f);
        });
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    s.opened.clear();
    remake_pieces(w, s, touched);
    if (by_copies) open_points_of_new_cuts(w, s, first_cut);
    // A front point that opened is now one side's copy: every piece still using it (an element
    // around its edge that the pass above did not make) is made again, until none is left.
    while (!s.opened.empty()) {
        const std::vector<std::array<int, 3>> opened = std::move(s.opened);
        s.opened.clear();
        std::vector<int> again;
        for (const auto& point : opened) {
            const int v = point[0];
            for_elements_around(w, point[1], point[2], [&](int f) {
                for (int t : s.pieces_of[f]) {
                    const auto& tri = s.triangles[t];
                    if (tri[0] == v || tri[1] == v || tri[2] == v) {
                        again.push_back(f);
                        return;
                    }
                }
            });
        }
        std::sort(again.begin(), again.end());
        again.erase(std::unique(again.begin(), again.end()), again.end());
        remake_pieces(w, s, again);
    }
    if (by_copies) merge_material_twins(w, s);
}

}  // namespace xcut
