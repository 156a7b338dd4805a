#include "systems/cut/stem_2d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <span>

#include "engine/fragment_geometry.h"
#include "systems/cut/material_anchor.h"
#include "systems/cut/recut.h"
#include "systems/kernels/intersection.h"
#include "systems/xfem_queries.h"

namespace xcut {

namespace {

/// The point of line's chord through the triangle with rest corners X nearest to q (its foot of
/// the perpendicular, or the chord's end nearer it); false if the line misses the triangle.
bool nearest_on_chord(const CutLine& line, const std::array<Vec3, 3>& X, const Vec3& q, Vec3& p) {
    const double size = longest_edge(X);
    const Vec3 along(-line.normal.y(), line.normal.x(), 0.0);
    const Vec3 a = line.origin - 2.0 * size * along, b = line.origin + 2.0 * size * along;
    const std::array<double, 2> chord = segment_in_polygon(a, b, {X.begin(), X.end()});
    if (!(chord[1] > chord[0])) return false;
    p = a + std::clamp((q - a).dot(along) / (4.0 * size), chord[0], chord[1]) * (b - a);
    return true;
}

/// How far line m of cut element e has opened at rest point `at` on it [m]: the farthest a fragment
/// it bounds carries that point (by its node copies' current triangle) from where e's own nodes
/// carry it. A blade's position inside e is taken to rest by e's own nodes, which stand for no
/// fragment once its lips have parted: a start in one lip's material lies up to this far off.
double opening_at(const World& w, int e, const std::array<Vec3, 3>& X, int m, const Vec3& at) {
    const int c = w.cuts.cut_of_element[e];
    const Vec3 b = triangle_barycentric(X, at);
    const Vec3 own = material_position(w, {e, b, -1});
    const bool first_only = w.cuts.lines[c].empty();
    double open = 0.0;
    for (const int v : fragments_of(w, c))
        if (first_only || (w.virtual_elements.mask[v] & bound_by(m)))
            open = std::max(open, (material_position(w, {e, b, v}) - own).norm());
    return open;
}

/// Where a blade's end inside cut element e (barycentric `at`, its stem from the rest crossing
/// `cross`) meets one of e's lines, as barycentric coordinates in e: the end itself, or, where a
/// line that does not part it from `cross` passes within the join distance of it inside e, the
/// nearest point of that line's chord through e (the foot of the perpendicular, or the chord's end
/// on an edge where the foot lies outside e: a blade that stops beside the point where the wound
/// leaves the element). The join distance is kJoinFraction of e's longest edge, and more by as much
/// as the line has opened at the foot (opening_at): a loop begun in a cross-cut's open wound, its
/// start in one lip's material, which e's own nodes put 0.59-0.67 mm from the line on 2 mm cells
/// and the lip's node copies 0.43 mm (loop stress seed 2, trajectories 424 and 965).
Vec3 end_on_wound(const World& w, int e, const std::array<Vec3, 3>& X, const Vec3& at, const Vec3& cross) {
    const double size = longest_edge(X), join = kJoinFraction * size;
    const Vec3 end = at.x() * X[0] + at.y() * X[1] + at.z() * X[2];
    Vec3 best = at;
    double nearest = std::numeric_limits<double>::infinity();
    const std::vector<CutLine> lines = lines_of(w, w.cuts.cut_of_element[e]);
    for (size_t m = 0; m < lines.size(); ++m) {
        const CutLine& line = lines[m];
        const double d = line.normal.dot(end - line.origin), dc = line.normal.dot(cross - line.origin);
        if ((d >= 0.0) != (dc >= 0.0) || std::abs(d) >= nearest) continue;
        const double limit = std::min(nearest, std::abs(d) < join ? join : join + opening_at(w, e, X, static_cast<int>(m), end - d * line.normal));
        if (std::abs(d) >= limit) continue;
        if (const Vec3 on = triangle_barycentric(X, end - d * line.normal); on.minCoeff() >= 0.0) {
            best = on, nearest = std::abs(d);
            continue;
        }
        Vec3 p;
        if (nearest_on_chord(line, X, end, p) && (p - end).norm() < limit)
            best = triangle_barycentric(X, p).cwiseMax(0.0), nearest = (p - end).norm();
    }
    return best;
}

/// The fragment of cut element e a blade came in to across its rest crossing
/// `cross` of an edge, heading for `p` (current): the one holding the start of the segment from
/// `cross` toward p as its node copies' current triangle maps p to rest (`end`). -1 if none.
int entered_fragment(const World& w, int e, const Vec3& cross, const Vec3& p, Vec3& end) {
    const int c = w.cuts.cut_of_element[e];
    if (c < 0) return -1;
    CutLine first;
    const std::span<const CutLine> lines = lines_in(w, c, first);
    for (const int v : fragments_of(w, c)) {
        const auto& n = w.elements.nodes[w.virtual_elements.element[v]];
        const std::array<Vec3, 3> x{w.nodes.position[n[0]], w.nodes.position[n[1]], w.nodes.position[n[2]]};
        end = material_rest(w, {e, triangle_barycentric(x, p), v});
        const auto part = segment_part(cross, end, lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v]);
        if (part[0] <= 0.0 && part[1] > part[0]) return v;
    }
    return -1;
}

/// The stem event of cut element e from its crossing of local edge k at t to the rest point of
/// barycentric coordinates l in e, bounded by them. False where it would pass through a node of
/// the edge, or has no length.
bool stem_between(const World& w, int e, int k, double t, const Vec3& l, CutEvent& ev) {
    const auto& n = w.elements.nodes[e];
    const std::array<Vec3, 3> x{w.nodes.position[n[0]], w.nodes.position[n[1]], w.nodes.position[n[2]]};
    const std::array<Vec3, 3> X = corners(w, e);
    const int i = kTriEdges[k][0], j = kTriEdges[k][1];
    const Vec3 exit = x[i] + t * (x[j] - x[i]);
    const Vec3 from = material_position(w, {e, l, -1});
    const Vec3 normal(from.y() - exit.y(), exit.x() - from.x(), 0.0);
    if (!(normal.norm() > 0.0)) return false;
    ev = CutEvent{};
    ev.element = e;
    ev.again = true;
    for (int a = 0; a < 3; ++a) ev.level[a] = (x[a] - from).dot(normal);
    if ((ev.level[i] >= 0.0) == (ev.level[j] >= 0.0)) return false;  // through a node of the edge
    ev.edge_t[k] = t, ev.edge_has_t[k] = 1;
    ev.bounded = true;
    ev.extent = {Vec3(l.x() * X[0] + l.y() * X[1] + l.z() * X[2]), Vec3(X[i] + t * (X[j] - X[i]))};
    return true;
}

}  // namespace

bool stem_event(const World& w, int e, int k, double t, const Vec3& start, CutEvent& ev) {
    const auto& n = w.elements.nodes[e];
    const std::array<Vec3, 3> x{w.nodes.position[n[0]], w.nodes.position[n[1]], w.nodes.position[n[2]]};
    const Vec3 at = triangle_barycentric(x, start);
    if (w.elements.dim != 2 || at.minCoeff() < 0.0) return false;
    const int i = kTriEdges[k][0], j = kTriEdges[k][1];
    const std::array<Vec3, 3> X = corners(w, e);
    // A blade that ends a hair short of the element's wound meets it (the tissue moved under it).
    return stem_between(w, e, k, t, end_on_wound(w, e, X, at, X[i] + t * (X[j] - X[i])), ev);
}

bool end_stem_event(const World& w, int e, int k, double t, const Vec3& end, CutEvent& ev) {
    if (stem_event(w, e, k, t, end, ev)) return true;
    if (w.elements.dim != 2) return false;
    const std::array<Vec3, 3> X = corners(w, e);
    const Vec3 cross = X[kTriEdges[k][0]] + t * (X[kTriEdges[k][1]] - X[kTriEdges[k][0]]);
    Vec3 rest;
    const int v = entered_fragment(w, e, cross, end, rest);
    if (v < 0) return false;
    CutLine first;
    const std::span<const CutLine> lines = lines_in(w, w.cuts.cut_of_element[e], first);
    const uint32_t mask = w.virtual_elements.mask[v];
    const double join = kJoinFraction * longest_edge(X);
    double nearest = join;
    Vec3 best = Vec3::Zero(), p;
    for (size_t m = 0; m < lines.size(); ++m) {
        const CutLine& line = lines[m];
        const double d = std::abs(line.normal.dot(rest - line.origin));
        if (!(mask & bound_by(static_cast<int>(m))) || d >= nearest) continue;
        if (nearest_on_chord(line, X, cross - line.normal.dot(cross - line.origin) * line.normal, p)) best = p, nearest = d;
    }
    return nearest < join && stem_between(w, e, k, t, triangle_barycentric(X, best).cwiseMax(0.0), ev);
}

bool wound_beside(const World& w, const MaterialPoint& end, uint8_t entered, Vec3& to) {
    const int e = end.element;
    if (w.elements.dim != 2 || e < 0 || e >= w.mesh_elements) return false;
    const std::array<Vec3, 3> X = corners(w, e);
    const Vec3 p = material_rest(w, end);
    double nearest = kJoinFraction * longest_edge(X);
    Vec3 point;
    if (const int c = w.cuts.cut_of_element[e]; c >= 0)
        for (const CutLine& line : lines_of(w, c))
            if (nearest_on_chord(line, X, p, point) && (point - p).norm() < nearest) return false;  // its stem meets it
    const auto& n = w.elements.nodes[e];
    int best = -1;
    Vec3 at;
    for (int k = 0; k < 3; ++k) {
        if (entered >> k & 1) continue;  // back out where it came in: a dip, not a meeting
        const int a = n[kTriEdges[k][0]], b = n[kTriEdges[k][1]];
        const int f = across_edge(w, e, a, b);
        if (f < 0 || w.cuts.cut_of_element[f] < 0) continue;
        const std::array<Vec3, 3> Y = corners(w, f);
        for (const CutLine& line : lines_of(w, w.cuts.cut_of_element[f])) {
            if (!nearest_on_chord(line, Y, p, point) || (point - p).norm() >= nearest) continue;
            if (!segment_segment_2d(p, point, w.nodes.rest[a], w.nodes.rest[b])) continue;  // not through edge (a, b)
            best = f, at = point, nearest = (point - p).norm();
        }
    }
    if (best < 0) return false;
    // Now: through the fragment on p's side of the line, a hair from it toward p.
    const int c = w.cuts.cut_of_element[best];
    const Vec3 inside = at + 1e-6 * (p - at);
    CutLine first;
    const std::span<const CutLine> lines = lines_in(w, c, first);
    const std::array<Vec3, 3> Y = corners(w, best);
    for (const int v : fragments_of(w, c)) {
        if (!in_fragment(lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v], inside)) continue;
        to = material_position(w, {best, triangle_barycentric(Y, at), v});
        return true;
    }
    return false;
}

bool queue_stem(World& w, int e, const ElementCrossings& c, const Vec3& start, int tool, bool ended) {
    const int k = __builtin_ctz(c.mask);
    CutEvent ev;
    if (!(ended ? end_stem_event(w, e, k, c.t[k], start, ev) : stem_event(w, e, k, c.t[k], start, ev))) return false;
    ev.tool = tool;
    w.pending_cuts.push_back(ev);
    return true;
}

}  // namespace xcut
