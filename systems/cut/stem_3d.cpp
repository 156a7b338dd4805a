#include "systems/cut/stem_3d.h"

#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"
#include "systems/cut/recut.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

/// The current positions of (force) element e's nodes: a mesh element's real nodes, a virtual
/// element's DOF nodes.
std::array<Vec3, 4> current_corners(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {w.nodes.position[n[0]], w.nodes.position[n[1]], w.nodes.position[n[2]], w.nodes.position[n[3]]};
}

/// Whether segment a -> b passes through tetrahedron x (its boundary included, to 1e-9 in
/// barycentric coordinates): the barycentric coordinates are affine along the segment, so the
/// segment's parameters where all four are >= 0 form one interval.
bool segment_meets_tet(const Vec3& a, const Vec3& b, const std::array<Vec3, 4>& x) {
    const Eigen::Vector4d la = tet_barycentric(x, a), lb = tet_barycentric(x, b);
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 4 && lo <= hi; ++k) {
        const double from = la[k] + 1e-9, slope = lb[k] - la[k];  // coordinate k + slack along s
        if (slope == 0.0) {
            if (from < 0.0) return false;
        } else if (slope > 0.0) {
            lo = std::max(lo, -from / slope);
        } else {
            hi = std::min(hi, -from / slope);
        }
    }
    return lo <= hi;
}

/// Current point p at rest by the affine field that takes mesh element e's rest corners to `x`
/// (extended beyond the element).
Vec3 at_rest(const World& w, int e, const std::array<Vec3, 4>& x, const Vec3& p) {
    const Eigen::Vector4d l = tet_barycentric(x, p);
    const auto& n = w.elements.nodes[e];
    Vec3 out = Vec3::Zero();
    for (int a = 0; a < 4; ++a) out += l[a] * w.nodes.rest[n[a]];
    return out;
}

/// The current corners of the fragment of cut element e (its virtual element's DOF nodes) whose
/// material is at current point p: the one whose own field maps p, at rest, into it. The element's
/// real nodes if none does.
std::array<Vec3, 4> material_ahead(const World& w, int e, const Vec3& p) {
    const int c = w.cuts.cut_of_element[e];
    for (int v : fragments_of(w, c)) {
        const std::array<Vec3, 4> x = current_corners(w, w.virtual_elements.element[v]);
        const Vec3 X = at_rest(w, e, x, p);
        bool holds = false;
        if (!w.cuts.lines[c].empty()) {
            holds = fragment_holds(w, c, v, X);
        } else {
            const CutLine l = first_cut_line(w, c);
            holds = (l.normal.dot(X - l.origin) >= 0.0) == (w.virtual_elements.side[v] > 0);
        }
        if (holds) return x;
    }
    return current_corners(w, e);
}

}  // namespace

void note_stem_starts(const World& w, BladeCut& bc, const CutQuad& q, const std::vector<int>& candidates) {
    if (w.elements.dim != 3 || !recut_allowed(w) || !bc.front.empty() || !bc.crossing.empty()) return;
    // The edge's line a blade length beyond either end: a blade lowered along its edge into the
    // wound (a stab, which sweeps nothing) began its quads higher than it reached.
    const Vec3 length = q.corner[1] - q.corner[0];
    const auto& cut = w.cuts.cut_of_element;
    for (int e : candidates)
        if (e < w.mesh_elements && !cut.empty() && cut[e] >= 0 && !bc.began_in.contains(e) &&
            segment_meets_tet(q.corner[0] - length, q.corner[1] + length, current_corners(w, e)))
            bc.began_in.emplace(e, std::array<Vec3, 2>{q.corner[0], q.corner[1]});
}

void note_stem_ends(const World& w, BladeCut& bc, const CutQuad& q) {
    if (w.elements.dim != 3 || !recut_allowed(w)) return;
    // A quad along the blade's own edge (the blade lifted out) sweeps no plane: the one before stays.
    const Vec3 length = q.corner[2] - q.corner[3], travel = q.corner[3] - q.corner[0];
    if (!(length.cross(travel).norm() > kStemStartFraction * length.norm() * travel.norm())) return;
    for (const auto& [e, c] : bc.crossing)
        if (w.cuts.cut_of_element[e] >= 0 && !c.split && segment_meets_tet(q.corner[3] - length, q.corner[2] + length, current_corners(w, e)))
            bc.ended_in[e] = {q.corner[3], q.corner[2], travel};
}

int end_stems_3d(World& w, BladeCut& bc, const std::vector<int>& leaving, int tool) {
    int made = 0;
    for (int e : leaving) {
        const auto end = bc.ended_in.find(e);
        const auto c = bc.crossing.find(e);
        if (end == bc.ended_in.end() || c == bc.crossing.end()) continue;
        const auto& [tip, heel, travel] = end->second;
        CutEvent ev;
        if (!stem_event_3d(w, e, {tip, heel}, tip - travel, c->second, ev)) continue;
        ev.tool = tool;
        w.pending_cuts.push_back(ev);
        ++made;
    }
    return made;
}

bool stem_event_3d(const World& w, int e, const std::array<Vec3, 2>& start, const Vec3& tip,
                   const ElementCrossings& c, CutEvent& ev) {
    const Vec3 along = start[1] - start[0], travel = tip - start[0];
    if (!(along.cross(travel).norm() > 1e-12 * along.norm() * travel.norm())) return false;
    const Vec3 edge = along.normalized(), n_now = along.cross(travel).normalized();
    const Vec3 ahead = (travel - travel.dot(edge) * edge).normalized();  // in the plane, across the edge
    // The edges its plane crosses ahead of the start (as the blade's crossings are measured, on the
    // real nodes now): the blade must have crossed each.
    const std::array<Vec3, 4> x = current_corners(w, e);
    const double tol_now = kStemStartFraction * longest_edge(x);
    uint8_t ahead_edges = 0;
    for (int k = 0; k < 6; ++k) {
        const int i = kTetEdges[k][0], j = kTetEdges[k][1];
        const double li = (x[i] - start[0]).dot(n_now), lj = (x[j] - start[0]).dot(n_now);
        if ((li >= 0.0) == (lj >= 0.0)) continue;
        if ((x[i] + li / (li - lj) * (x[j] - x[i]) - start[0]).dot(ahead) > tol_now) ahead_edges |= uint8_t(1u << k);
    }
    if (ahead_edges == 0 || (c.mask & ahead_edges) != ahead_edges) return false;
    // The plane at rest by the field of the material the blade is in ahead of its start: the wound's
    // lips have moved apart, so the element's real nodes (some on each lip) do not map it to rest.
    const std::array<Vec3, 4> m = material_ahead(w, e, start[0] + tol_now * ahead);
    const std::array<Vec3, 4> X = tet_corners(w, e);
    const Vec3 s0 = at_rest(w, e, m, start[0]), s1 = at_rest(w, e, m, start[1]), t1 = at_rest(w, e, m, tip);
    const Vec3 normal = (s1 - s0).cross(t1 - s0);
    Vec3 bound = normal.cross(s1 - s0);
    if (!(normal.norm() > 0.0) || !(bound.norm() > 0.0)) return false;
    bound.normalize();
    if (bound.dot(t1 - s0) < 0.0) bound = -bound;
    ev = CutEvent{};
    ev.element = e;
    ev.again = true;
    for (int a = 0; a < 4; ++a) ev.level[a] = (X[a] - s0).dot(normal.normalized());  // at rest: one plane
    // Where it crosses an edge within kStemStartFraction of where a cut of the element does (the T's
    // junction, on the edge through both), it crosses there: a hair ahead of the wound, it would
    // leave the part of the element across the wound (which it does not divide) a sliver on its other
    // side, joining the flaps.
    const int cut = w.cuts.cut_of_element[e];
    for (int k = 0; k < 6; ++k) {
        const double li = ev.level[kTetEdges[k][0]], lj = ev.level[kTetEdges[k][1]];
        if ((li >= 0.0) == (lj >= 0.0)) continue;
        const double t = li / (li - lj);
        for (size_t l = 0; l < std::max<size_t>(1, w.cuts.lines[cut].size()); ++l)
            if (const double u = line_edge_params(w, cut, l)[k]; u > 0.0 && u < 1.0 && std::abs(u - t) < kStemStartFraction)
                ev.edge_t[k] = u, ev.edge_has_t[k] = 1;
    }
    ev.bounded = true;
    ev.extent = {s0, bound};
    return true;
}

bool stem_covers(const CutEvent& ev, const std::vector<Vec3>& section, double size) {
    if (section.empty()) return false;
    return std::all_of(section.begin(), section.end(),
                       [&](const Vec3& p) { return (p - ev.extent[0]).dot(ev.extent[1]) >= -kStemStartFraction * size; });
}

}  // namespace xcut
