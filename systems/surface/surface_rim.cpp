// The cut inside one element as the surface sees it: the plane and the trace the cut leaves on each
// face, the side of a point, and the rim of the cut face in order around the cut (paper §3.4, Fig. 6;
// systems/surface/surface_cut_parts.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "systems/kernels/cut_geometry.h"
#include "systems/surface/surface_cut_parts.h"

namespace xcut {
namespace surface_cut_detail {
namespace {

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

/// The plane through cp.points (their centroid; 2D: normal to the segment, 3D: the largest normal
/// of any three points, as a quad's points stored by edge may be a bow-tie where Newell's sum
/// cancels) and each node's level and the orientation, for cut element e.
void fit_cut_plane(const World& w, int e, CutPlaneInfo& cp) {
    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    const auto& p = cp.points;
    cp.origin = Vec3::Zero();
    for (const Vec3& x : p) cp.origin += x / static_cast<double>(p.size());
    cp.normal = chord_normal(p.data(), static_cast<int>(p.size()), el.dim);
    int far = 0;
    for (int a = 0; a < npe; ++a) {
        cp.phi[a] = cp.normal.dot(w.nodes.rest[el.nodes[e][a]] - cp.origin);
        if (std::abs(cp.phi[a]) > std::abs(cp.phi[far])) far = a;
    }
    cp.orient = (cp.phi[far] >= 0) == (w.enriched.sign[el.nodes[e][far]] > 0) ? 1.0 : -1.0;
}

/// The edge points of cut element e as the surface uses them (surface_edge_param), and the plane
/// through them: a skin vertex the cut passes through (a subdivision point the crossing was moved
/// off) then lies clearly on the side its edge's crossing gives it, so the skin's own crossings
/// near it are made on the cut, not at the vertex.
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

}  // namespace

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

}  // namespace surface_cut_detail

using namespace surface_cut_detail;

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
        double t = edge_crossing(w, en[i], en[j]);  // from node i
        if (several_per_edge(w))  // several incisions may cross it: this cut's own crossing
            for (size_t k = 0; k < cp.points.size(); ++k) {
                const int* ed = local_edge(w, cp.point_edge[k]);
                const Vec3 &Xi = w.nodes.rest[en[i]], d = w.nodes.rest[en[j]] - Xi;
                if ((ed[0] == i && ed[1] == j) || (ed[0] == j && ed[1] == i))
                    t = surface_edge_param(en[i], en[j], (cp.points[k] - Xi).dot(d) / d.squaredNorm());
            }
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

}  // namespace xcut
