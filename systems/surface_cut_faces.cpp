// The wound's closing faces inside a cut element: the cut face as one polygon per side over the
// element's edge points and the skin's crossings, oriented outward, and the seams that join the two
// lips along the crack front (paper §3.4, Fig. 6; systems/surface_cut_parts.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "systems/surface_cut_parts.h"

namespace xcut::surface_cut_detail {
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

void cut_faces(World& w, SurfaceMesh& s, int c, const CutPlaneInfo& cp, const std::vector<RimPoint>& rim) {
    const int e = w.cuts.element[c];
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

}  // namespace xcut::surface_cut_detail
