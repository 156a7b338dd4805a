// The wound's closing faces inside a cut element: the cut face as one polygon per side over the
// element's edge points and the skin's crossings, oriented outward (paper §3.4, Fig. 6;
// systems/surface/surface_cut_parts.h). Along the crack front the two polygons share their points (one
// vertex per front point, surface_points.cpp): the lips meet there, with no seam between them.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "systems/surface/surface_cut_parts.h"

namespace xcut::surface_cut_detail {
namespace {

/// Triangulates one side's cut polygon `loop` (outward order) of cut element e: three points give
/// one triangle, four give two split along the diagonal the Delaunay criterion picks (the angles
/// facing it sum to less than pi) unless it joins two front points, more (skin crossing points on
/// the rim, parting points) a fan around the centre.
template <class Shared>
void close_polygon(World& w, SurfaceMesh& s, int e, int side, const std::vector<int>& loop,
                   const Eigen::Vector4d& centre, const Shared& shared, bool fan) {
    if (loop.size() == 3 && !fan) {
        add_piece(s, {loop[0], loop[1], loop[2]}, e, true);
        return;
    }
    if (loop.size() == 4 && !fan) {
        auto angle = [&](int at, int p, int q) {
            const Vec3 x = vertex_rest(w, s, at);
            const Vec3 a = vertex_rest(w, s, p) - x, b = vertex_rest(w, s, q) - x;
            return std::atan2(a.cross(b).norm(), a.dot(b));
        };
        const auto& l = loop;
        // A diagonal between two front points would be an edge of both lips: the other one.
        const bool pinned02 = shared(l[0]) && shared(l[2]), pinned13 = shared(l[1]) && shared(l[3]);
        const bool delaunay02 = angle(l[1], l[0], l[2]) + angle(l[3], l[2], l[0]) <= M_PI;
        if (pinned13 || (delaunay02 && !pinned02)) {  // diagonal 0-2
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

/// Whether `loop` (rest positions), as ordered, faces away from `side`'s material: its area vector
/// (Newell's sum) points from the element's nodes on `side` toward those on the other. A cut
/// through nodes whose sides an earlier incision fixed need not be planar, and the plane fitted
/// through its points can leave a node on the wrong side of it (two incisions meeting: stress
/// trajectory 3113 of the multi-blade record), so the nodes' own sides decide. Where the loop has
/// no area along that direction, the fitted plane's orientation does: the loop runs
/// counter-clockwise about the cut's normal.
bool faces_its_other_side(const World& w, const SurfaceMesh& s, int e, int side, const std::vector<int>& loop,
                          const CutPlaneInfo& cp) {
    Vec3 area = Vec3::Zero(), own = Vec3::Zero(), other = Vec3::Zero();
    for (size_t k = 0; k < loop.size(); ++k)
        area += vertex_rest(w, s, loop[k]).cross(vertex_rest(w, s, loop[(k + 1) % loop.size()]));
    int n_own = 0, n_other = 0;
    const auto& nodes = w.elements.nodes[e];
    for (int a = 0; a < 4; ++a) {
        const bool mine = w.enriched.sign[nodes[a]] == side;
        (mine ? own : other) += w.nodes.rest[nodes[a]];
        (mine ? n_own : n_other) += 1;
    }
    const Vec3 across = other / n_other - own / n_own;
    const double facing = area.dot(across);
    if (std::abs(facing) > 1e-6 * area.norm() * across.norm()) return facing > 0.0;
    return side * cp.orient < 0;
}

}  // namespace

void cut_faces(World& w, SurfaceMesh& s, int c, const CutPlaneInfo& cp, const std::vector<RimPoint>& rim) {
    const int e = w.cuts.element[c];
    std::vector<Eigen::Vector4d> edge_points;
    const auto& nodes = w.elements.nodes[e];
    for (size_t k = 0; k < cp.points.size(); ++k) {
        const int* ed = kTetEdges[cp.point_edge[k]];
        const Vec3 Xi = w.nodes.rest[nodes[ed[0]]], Xj = w.nodes.rest[nodes[ed[1]]];
        edge_points.push_back(on_edge(ed[0], ed[1], (cp.points[k] - Xi).dot(Xj - Xi) / (Xj - Xi).squaredNorm()));
    }
    Eigen::Vector4d centre = Eigen::Vector4d::Zero();
    for (const RimPoint& r : rim) centre += r.b / static_cast<double>(rim.size() + edge_points.size());
    for (const auto& b : edge_points) centre += b / static_cast<double>(rim.size() + edge_points.size());
    const std::vector<Eigen::Vector4d> around = cut_rim_loop(w, e, cp, edge_points, rim);
    std::array<std::vector<int>, 2> loops;  // the + side's and the - side's, in `around`'s order
    for (int k = 0; k < 2; ++k)
        for (const Eigen::Vector4d& b : around) {
            const int id = surface_point(w, s, e, k == 0 ? 1 : -1, b);
            // Each point once: a rim point at an edge point's place (the skin's crossing on a
            // crossed element edge) is that point.
            if (std::find(loops[k].begin(), loops[k].end(), id) == loops[k].end()) loops[k].push_back(id);
        }
    // Points of both loops are on the crack front: one vertex where the lips meet.
    std::vector<int> shared;
    for (int v : loops[0])
        if (std::find(loops[1].begin(), loops[1].end(), v) != loops[1].end()) shared.push_back(v);
    const auto is_shared = [&](int v) { return std::find(shared.begin(), shared.end(), v) != shared.end(); };
    // Where both ends of an edge of a loop are front points but the lips part between them, the
    // loop goes through its side's parting point.
    for (int k = 0; k < 2; ++k) {
        std::vector<int>& loop = loops[k];
        for (size_t q = 0; q < loop.size(); ++q) {
            const int u = loop[q], v = loop[(q + 1) % loop.size()];
            const int mid = is_shared(u) && is_shared(v) ? parting_point(w, s, e, k == 0 ? 1 : -1, u, v, false) : -1;
            if (mid >= 0) loop.insert(loop.begin() + static_cast<std::ptrdiff_t>(++q), mid);
        }
    }
    // Where another incision's wound, in an element cut again across a face, ends on an edge of a
    // loop, the loop goes through that point (surface_fragments.cpp: further_crossings), and is
    // fanned round its centre (the point lies on the edge).
    bool further = false;
    for (int k = 0; k < 2; ++k) {
        const int side = k == 0 ? 1 : -1;
        const int fe = w.virtual_elements.element[w.cuts.virtual_element[c][k]];
        std::vector<int>& loop = loops[k];
        std::vector<int> with;
        for (size_t q = 0; q < loop.size(); ++q) {
            const int u = loop[q], v = loop[(q + 1) % loop.size()];
            with.push_back(u);
            const Eigen::Vector4d bu = local_bary(w, s, e, u), bv = local_bary(w, s, e, v);
            for (const auto& [t, x] : further_crossings(w, e, vertex_rest(w, s, u), vertex_rest(w, s, v), bu, bv)) {
                with.push_back(shared_point(w, s, fe, static_cast<int8_t>(side), (1.0 - t) * bu + t * bv, x));
                further = true;
            }
        }
        loop = std::move(with);
    }
    // Every point and edge on the front: the lips meet all round and cannot part; no faces.
    if (std::all_of(loops[0].begin(), loops[0].end(), is_shared) && loops[0].size() == loops[1].size()) return;
    for (int k = 0; k < 2; ++k) {
        const int side = k == 0 ? 1 : -1;
        std::vector<int>& loop = loops[k];
        if (loop.size() < 3) continue;
        // Outward for this side's piece is away from its own material, toward the other side.
        if (!faces_its_other_side(w, s, e, side, loop, cp)) std::reverse(loop.begin(), loop.end());
        close_polygon(w, s, e, side, loop, centre, is_shared, further);
    }
}

}  // namespace xcut::surface_cut_detail
