#include "systems/surface_cut.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "components/cut_elements.h"

namespace xcut {
namespace {

constexpr double kQuantum = 1e-11;  // [m]: points closer than this on one side are one point

Vec3 rest_of(const World& w, int e, const Eigen::Vector4d& b) {
    Vec3 x = Vec3::Zero();
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) x += b[a] * w.nodes.rest[w.elements.nodes[e][a]];
    return x;
}

/// A vertex's barycentric coordinates re-expressed in mesh element e (the vertex lies on e's
/// boundary, so every node it is weighted on is one of e's).
Eigen::Vector4d local_bary(const World& w, int e, int v) {
    const auto& own = w.elements.nodes[w.visual.element[v]];
    const auto& target = w.elements.nodes[e];
    const int npe = w.elements.nodes_per_element();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    for (int a = 0; a < npe; ++a) {
        if (w.visual.bary[v][a] == 0.0) continue;
        int node = own[a];
        if (node >= w.mesh_nodes) node = w.enriched.node_of_phantom[node - w.mesh_nodes];
        for (int k = 0; k < npe; ++k)
            if (target[k] == node) b[k] += w.visual.bary[v][a];
    }
    return b;
}

/// Rest position of a surface vertex, from its own element (phantoms rest where their node does).
Vec3 vertex_rest(const World& w, int v) {
    const auto& nodes = w.elements.nodes[w.visual.element[v]];
    Vec3 x = Vec3::Zero();
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) x += w.visual.bary[v][a] * w.nodes.rest[nodes[a]];
    return x;
}

/// The vertex on `side` at barycentric `b` of cut element c's parent (made once per side/place).
int cut_vertex(World& w, int c, int side, const Eigen::Vector4d& b) {
    SurfaceMesh& s = w.visual;
    const int e = w.cuts.element[c];
    const Vec3 x = rest_of(w, e, b);
    const std::array<int64_t, 4> key = {side, std::llround(x.x() / kQuantum), std::llround(x.y() / kQuantum),
                                        std::llround(x.z() / kQuantum)};
    auto [it, fresh] = s.cut_point.emplace(key, s.vertex_count());
    if (!fresh) return it->second;
    const int fe = w.virtual_elements.element[w.cuts.virtual_element[c][side > 0 ? 0 : 1]];
    s.position.push_back(x);
    s.element.push_back(fe);
    s.bary.push_back(b);
    s.bound_to[e].push_back(it->second);
    return it->second;
}

void add_triangle(World& w, const std::array<int, 3>& t, int owner, bool cut) {
    SurfaceMesh& s = w.visual;
    s.triangles.push_back(t);
    s.triangle_owner.push_back(owner);
    s.cut_face.push_back(cut ? 1 : 0);
    if (!cut) s.triangles_of[owner].push_back(static_cast<int>(s.triangles.size()) - 1);
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
            const int* ed = w.elements.dim == 3 ? kTetEdges[cp.point_edge[k]] : kTriEdges[cp.point_edge[k]];
            if (!((ed[0] == i && ed[1] == j) || (ed[0] == j && ed[1] == i))) continue;
            // The point's barycentric weight on node i, and those of a and b: solve along the edge.
            const Vec3 Xi = w.nodes.rest[w.elements.nodes[e][i]], Xj = w.nodes.rest[w.elements.nodes[e][j]];
            const double tp = (cp.points[k] - Xi).dot(Xj - Xi) / (Xj - Xi).squaredNorm();
            const double ta = ba[j], tb = bb[j];
            if (ta == tb) break;
            return std::clamp((tp - ta) / (tb - ta), 0.0, 1.0);
        }
    }
    double la = 0.0, lb = 0.0;
    for (int a = 0; a < npe; ++a) la += ba[a] * cp.phi[a], lb += bb[a] * cp.phi[a];
    return la != lb ? std::clamp(la / (la - lb), 0.0, 1.0) : 0.5;
}

}  // namespace

CutPlaneInfo cut_plane_info(const World& w, int c) {
    const Elements& el = w.elements;
    const int e = w.cuts.element[c], npe = el.nodes_per_element();
    CutPlaneInfo cp;
    for (int k = 0; k < 4; ++k)
        if (w.cuts.point_edge[c][k] >= 0) {
            cp.points.push_back(w.cuts.points[c][k]);
            cp.point_edge.push_back(w.cuts.point_edge[c][k]);
        }
    for (const Vec3& p : cp.points) cp.origin += p / static_cast<double>(cp.points.size());
    if (el.dim == 2) {
        const Vec3 d = cp.points[1] - cp.points[0];
        cp.normal = Vec3(-d.y(), d.x(), 0.0);
    } else {
        // The points are stored by edge, not around the polygon (a quad's order may be a bow-tie,
        // where Newell's sum cancels): take the largest normal of any three of them.
        const auto& p = cp.points;
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
    return cp;
}

void cut_surface(World& w, int c) {
    SurfaceMesh& s = w.visual;
    const int e = w.cuts.element[c];
    const CutPlaneInfo cp = cut_plane_info(w, c);
    // Skin crossing points per side, for the cut faces' rims.
    std::vector<Eigen::Vector4d> rim;
    const std::vector<int> owned = s.triangles_of[e];
    s.triangles_of[e].clear();
    const int npe = w.elements.nodes_per_element();
    for (int t : owned) {
        const auto tri = s.triangles[t];
        std::array<int, 3> side;
        std::array<Eigen::Vector4d, 3> lb;
        for (int k = 0; k < 3; ++k) {
            lb[k] = local_bary(w, e, tri[k]);
            side[k] = 0;
            for (int a = 0; a < npe; ++a)
                if (lb[k][a] == 1.0) side[k] = w.enriched.sign[w.elements.nodes[e][a]];  // at a node: its H
            if (side[k] == 0) {
                double level = 0.0;
                for (int a = 0; a < npe; ++a) level += lb[k][a] * cp.phi[a];
                side[k] = cp.orient * level >= 0.0 ? 1 : -1;
            }
        }
        int lone = -1;
        for (int k = 0; k < 3; ++k)
            if (side[k] != side[(k + 1) % 3] && side[k] != side[(k + 2) % 3]) lone = k;
        if (lone < 0) {  // not crossed: keep
            s.triangles_of[e].push_back(t);
            continue;
        }
        const int L = tri[lone], M1 = tri[(lone + 1) % 3], M2 = tri[(lone + 2) % 3];
        const Eigen::Vector4d &bL = lb[lone], &bM1 = lb[(lone + 1) % 3], &bM2 = lb[(lone + 2) % 3];
        const double s1 = crossing_param(w, cp, e, bL, bM1);
        const double s2 = crossing_param(w, cp, e, bL, bM2);
        const Eigen::Vector4d b1 = (1 - s1) * bL + s1 * bM1;
        const Eigen::Vector4d b2 = (1 - s2) * bL + s2 * bM2;
        rim.push_back(b1);
        rim.push_back(b2);
        const int sl = side[lone], sm = -sl;
        const int x1l = cut_vertex(w, c, sl, b1), x2l = cut_vertex(w, c, sl, b2);
        const int x1m = cut_vertex(w, c, sm, b1), x2m = cut_vertex(w, c, sm, b2);
        s.triangles[t] = {L, x1l, x2l};  // the lone corner keeps the slot
        s.triangles_of[e].push_back(t);
        add_triangle(w, {x1m, M1, M2}, e, false);
        add_triangle(w, {x1m, M2, x2m}, e, false);
    }
    if (w.elements.dim == 2) return;  // in 2D the surface is the sheet itself: the gap is the cut

    // The internal mesh: edge points and rim points around the cut, a fan per side.
    std::vector<Eigen::Vector4d> ring = rim;
    const auto& nodes = w.elements.nodes[e];
    for (size_t k = 0; k < cp.points.size(); ++k) {
        const int* ed = kTetEdges[cp.point_edge[k]];
        const Vec3 Xi = w.nodes.rest[nodes[ed[0]]], Xj = w.nodes.rest[nodes[ed[1]]];
        const double t = (cp.points[k] - Xi).dot(Xj - Xi) / (Xj - Xi).squaredNorm();
        Eigen::Vector4d b = Eigen::Vector4d::Zero();
        b[ed[0]] = 1 - t, b[ed[1]] = t;
        ring.push_back(b);
    }
    const Vec3 u = cp.normal.unitOrthogonal(), v = cp.normal.cross(u);
    Eigen::Vector4d centre = Eigen::Vector4d::Zero();
    for (const auto& b : ring) centre += b / static_cast<double>(ring.size());
    const Vec3 xc = rest_of(w, e, centre);
    std::vector<std::pair<double, Eigen::Vector4d>> around;
    for (const auto& b : ring) {
        const Vec3 d = rest_of(w, e, b) - xc;
        around.emplace_back(std::atan2(d.dot(v), d.dot(u)), b);
    }
    std::sort(around.begin(), around.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (int side : {1, -1}) {
        std::vector<int> loop;
        for (const auto& [angle, b] : around) {
            const int id = cut_vertex(w, c, side, b);
            if (loop.empty() || (loop.back() != id && loop.front() != id)) loop.push_back(id);
        }
        if (loop.size() < 3) continue;
        const int hub = cut_vertex(w, c, side, centre);
        // Outward for this side's piece: away from its own material, i.e. toward the other side.
        const Vec3 outward = -side * cp.orient * cp.normal;
        for (size_t k = 0; k < loop.size(); ++k) {
            std::array<int, 3> t = {hub, loop[k], loop[(k + 1) % loop.size()]};
            const Vec3 p0 = vertex_rest(w, t[0]);
            const Vec3 n = (vertex_rest(w, t[1]) - p0).cross(vertex_rest(w, t[2]) - p0);
            if (n.dot(outward) < 0) std::swap(t[1], t[2]);
            add_triangle(w, t, e, true);
        }
    }
}

}  // namespace xcut
