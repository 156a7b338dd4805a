#include "systems/cut/scripted_cut_system.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "systems/cut/edge_geometry.h"
#include "systems/cut/recut.h"
#include "systems/kernels/mesh_measures.h"

namespace xcut {
namespace {

struct CutPlane {
    Vec3 origin, normal, u, v;   ///< u, v span the plane (3D); 2D: u along the segment
    double length = 0.0;         ///< 2D: segment length [m]
};

CutPlane plane_of(const std::vector<Vec3>& poly, int dim) {
    CutPlane p;
    p.origin = Vec3::Zero();
    for (const Vec3& q : poly) p.origin += q;
    p.origin /= static_cast<double>(poly.size());
    if (dim == 2) {
        const Vec3 d = poly[1] - poly[0];
        p.length = d.norm();
        p.u = d / p.length;
        p.normal = Vec3(-p.u.y(), p.u.x(), 0.0);
        p.origin = poly[0];
        return p;
    }
    Vec3 n = Vec3::Zero();  // Newell's normal: robust for any planar polygon
    for (size_t i = 0; i < poly.size(); ++i) n += poly[i].cross(poly[(i + 1) % poly.size()]);
    p.normal = n.normalized();
    p.u = (poly[0] - p.origin).normalized();
    p.v = p.normal.cross(p.u);
    return p;
}

/// Even-odd test of q (on the plane) against the polygon; points on an edge count as inside.
bool inside_polygon(const CutPlane& pl, const std::vector<Vec3>& poly, const Vec3& q) {
    const double x = (q - pl.origin).dot(pl.u), y = (q - pl.origin).dot(pl.v);
    bool in = false;
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const double xi = (poly[i] - pl.origin).dot(pl.u), yi = (poly[i] - pl.origin).dot(pl.v);
        const double xj = (poly[j] - pl.origin).dot(pl.u), yj = (poly[j] - pl.origin).dot(pl.v);
        const double cross = (xj - xi) * (y - yi) - (yj - yi) * (x - xi);
        const double scale = 1e-12 * (std::abs(xj - xi) + std::abs(yj - yi)) * (std::abs(x - xi) + std::abs(y - yi) + 1e-300);
        if (std::abs(cross) <= scale && (x - xi) * (x - xj) <= 0.0 && (y - yi) * (y - yj) <= 0.0) return true;
        if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) in = !in;
    }
    return in;
}

bool inside_segment(const CutPlane& pl, const Vec3& q) {
    const double s = (q - pl.origin).dot(pl.u);
    const double eps = 1e-12 * pl.length;
    return s >= -eps && s <= pl.length + eps;
}

/// A 2D segment that ends inside cut element e (its line crossing two of its edges, ev.edge_t):
/// the event's extent, the part of the segment inside e, at rest. The map from the current line to
/// the rest one is affine inside a linear element, so it runs from one crossing to the other.
/// False if the segment misses e.
bool bound_recut(const World& w, int e, const CutPlane& pl, CutEvent& ev, const std::vector<Vec3>* x) {
    std::array<double, 2> s{};
    std::array<Vec3, 2> rest;
    int n = 0;
    for (int k = 0; k < 3 && n < 2; ++k) {
        if (!ev.edge_has_t[k]) continue;
        const Vec3& Xi = w.nodes.rest[w.elements.nodes[e][kTriEdges[k][0]]];
        const Vec3& Xj = w.nodes.rest[w.elements.nodes[e][kTriEdges[k][1]]];
        s[n] = (edge_point(w, e, k, ev.edge_t[k], x) - pl.origin).dot(pl.u);
        rest[n++] = Xi + ev.edge_t[k] * (Xj - Xi);
    }
    if (n < 2 || s[0] == s[1]) return false;
    const double lo = std::max(std::min(s[0], s[1]), 0.0), hi = std::min(std::max(s[0], s[1]), pl.length);
    if (!(lo < hi)) return false;
    const auto at = [&](double q) { return Vec3(rest[0] + (q - s[0]) / (s[1] - s[0]) * (rest[1] - rest[0])); };
    ev.bounded = true;
    ev.extent = {at(lo), at(hi)};
    return true;
}

/// Whether the plane runs through every point of cut element e's first cut (nodes at x, within
/// 1e-9 of its longest edge): the same cut again, not another one.
bool along_first_cut(const World& w, int e, const CutPlane& pl, const std::vector<Vec3>& x) {
    const int c = w.cuts.cut_of_element[e];
    double size = 0.0;
    for (int k = 0; k < edge_count(w.elements.dim); ++k) {
        const int* ed = edge_nodes(w.elements.dim, k);
        size = std::max(size, (x[w.elements.nodes[e][ed[0]]] - x[w.elements.nodes[e][ed[1]]]).norm());
    }
    for (int p = 0; p < 4; ++p) {
        const int k = w.cuts.point_edge[c][p];
        if (k < 0) continue;
        const int* ed = edge_nodes(w.elements.dim, k);
        const Vec3& Xi = w.nodes.rest[w.elements.nodes[e][ed[0]]];
        const Vec3& Xj = w.nodes.rest[w.elements.nodes[e][ed[1]]];
        const double t = (w.cuts.points[c][p] - Xi).norm() / (Xj - Xi).norm();
        if (std::abs((edge_point(w, e, k, t, &x) - pl.origin).dot(pl.normal)) > 1e-9 * size) return false;
    }
    return true;
}

}  // namespace

int queue_polygon_cut(World& w, const std::vector<Vec3>& polygon, bool progressive, bool at_rest) {
    const std::vector<Vec3>& x = at_rest ? w.nodes.rest : w.nodes.position;  // where the polygon is drawn
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element();
    const CutPlane pl = plane_of(polygon, dim);
    const auto& cut = w.cuts.cut_of_element;
    int queued = 0;
    const bool again = recut_allowed(w);
    for (int e = 0; e < w.mesh_elements; ++e) {
        const bool is_cut = !cut.empty() && cut[e] >= 0;
        // An element already cut that this world cannot cut again (or that holds its last line):
        // crossed along another plane, it keeps its cuts, and the count says so.
        const bool full = is_cut && (!again || static_cast<int>(lines_of(w, cut[e]).size()) >= kMaxElementLines);
        CutEvent ev;
        ev.again = is_cut;
        ev.element = e;
        // The sides of this cut's plane. Not the sides earlier cuts fixed: a node an earlier cut put
        // on one side lies on either side of this one, and an element this plane does not cross is
        // not split (the EnrichmentSystem orients the split by the fixed sides).
        std::array<int8_t, 4> H{};
        for (int a = 0; a < npe; ++a) {
            ev.level[a] = (x[el.nodes[e][a]] - pl.origin).dot(pl.normal);
            H[a] = ev.level[a] >= 0.0 ? 1 : -1;
        }
        bool crossed = false, complete = true;
        uint8_t inside = 0;  // the edges crossed inside the polygon
        const int edges = dim == 3 ? 6 : 3;
        for (int k = 0; k < edges && (complete || progressive || is_cut); ++k) {
            const int* ed = edge_nodes(dim, k);
            if (H[ed[0]] == H[ed[1]]) continue;
            const double t = plane_edge_param(w, e, k, pl.origin, pl.normal, &x);
            const Vec3 q = edge_point(w, e, k, t, &x);
            const bool in = dim == 3 ? inside_polygon(pl, polygon, q) : inside_segment(pl, q);
            complete = complete && in;
            inside |= static_cast<uint8_t>(in) << k;
            ev.edge_t[k] = t;
            ev.edge_has_t[k] = 1;
            crossed = true;
        }
        if (full) {
            if (crossed && complete && !along_first_cut(w, e, pl, x)) ++w.cut_plan.recut_ignored;
            continue;
        }
        if (crossed && is_cut && !complete) {  // cut again up to where the segment ends inside it
            if (dim != 2 || !bound_recut(w, e, pl, ev, &x)) continue;
            w.pending_cuts.push_back(ev);
            ++queued;
            continue;
        }
        if (crossed && (complete || (progressive && inside != 0))) {
            if (!complete) ev.crossed = inside;  // a tip element: its other split edges are held
            w.pending_cuts.push_back(ev);
            ++queued;
        }
    }
    return queued;
}

SystemDesc scripted_cut_system() {
    return {"ScriptedCutSystem", kNodes | kElements | kCutPlan, kCutEvents | kCutPlan, [](World& w) {
                for (ScriptedCut& c : w.cut_plan.cuts) {
                    if (c.applied || c.time > w.time + 1e-12) continue;
                    queue_polygon_cut(w, c.polygon, false, c.at_rest);
                    c.applied = true;
                }
            }};
}

}  // namespace xcut
