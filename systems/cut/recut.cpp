#include "systems/cut/recut.h"

#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"
#include "engine/setup.h"
#include "systems/cut/enrichment_system.h"
#include "systems/cut/stem_3d.h"
#include "systems/kernels/cut_geometry.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/xfem_queries.h"

namespace xcut {

std::array<Vec3, 3> corners(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {w.nodes.rest[n[0]], w.nodes.rest[n[1]], w.nodes.rest[n[2]]};
}

std::array<Vec3, 4> tet_corners(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {w.nodes.rest[n[0]], w.nodes.rest[n[1]], w.nodes.rest[n[2]], w.nodes.rest[n[3]]};
}

namespace {

/// The plane through points p[0..np) (3D), its normal toward the corners' positive `level` side.
CutLine plane_through(const Vec3* p, int np, const std::array<Vec3, 4>& X, const std::array<double, 4>& level) {
    CutLine l{p[0], chord_normal(p, np, 3)};
    double toward = 0.0;
    for (int a = 0; a < 4; ++a) toward += level[a] * l.normal.dot(X[a] - p[0]);
    if (toward < 0.0) l.normal = -l.normal;
    return l;
}

/// The line through a and b, its normal toward the corners' positive `level` side.
CutLine line_through(const Vec3& a, const Vec3& b, const std::array<Vec3, 3>& X, const std::array<double, 3>& level) {
    CutLine l{a, Vec3(a.y() - b.y(), b.x() - a.x(), 0.0).normalized()};
    double toward = 0.0;
    for (int k = 0; k < 3; ++k) toward += level[k] * l.normal.dot(X[k] - a);
    if (toward < 0.0) l.normal = -l.normal;
    return l;
}

/// Gives cut element c its first line and its two sides as fragments, if it has none yet.
void ensure_lines(World& w, int c) {
    CutElements& ce = w.cuts;
    if (!ce.lines[c].empty()) return;
    ce.lines[c].push_back(first_cut_line(w, c));
    if (w.elements.dim == 3) ce.line_edge_t[c].assign(1, first_edge_params(w, c));
    ce.fragments[c] = {ce.virtual_element[c][0], ce.virtual_element[c][1]};
}

}  // namespace

CutLine first_cut_line(const World& w, int c) {
    const int e = w.cuts.element[c];
    if (w.elements.dim == 3) {
        std::array<double, 4> level{};
        for (int a = 0; a < 4; ++a) level[a] = w.enriched.sign[w.elements.nodes[e][a]];
        std::array<Vec3, 4> p;
        int np = 0;
        for (int k = 0; k < 4; ++k)
            if (w.cuts.point_edge[c][k] >= 0) p[np++] = w.cuts.points[c][k];
        return plane_through(p.data(), np, tet_corners(w, e), level);
    }
    std::array<double, 3> level{};
    for (int a = 0; a < 3; ++a) level[a] = w.enriched.sign[w.elements.nodes[e][a]];
    return line_through(w.cuts.points[c][0], w.cuts.points[c][1], corners(w, e), level);
}

bool fragment_holds(const World& w, int c, int v, const Vec3& x) {
    const auto& lines = w.cuts.lines[c];
    return in_fragment(lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v], x);
}

std::span<const CutLine> lines_in(const World& w, int c, CutLine& first) {
    if (!w.cuts.lines[c].empty()) return w.cuts.lines[c];
    first = first_cut_line(w, c);
    return {&first, 1};
}

std::vector<CutLine> lines_of(const World& w, int c) {
    CutLine first;
    const std::span<const CutLine> lines = lines_in(w, c, first);
    return {lines.begin(), lines.end()};
}

bool cuts_across(const World& w, int e, const Vec3& normal) {
    const int c = w.cuts.cut_of_element[e];
    const double n = normal.norm();
    if (c < 0 || !(n > 0.0)) return false;
    CutLine first;
    const std::span<const CutLine> lines = lines_in(w, c, first);
    if (static_cast<int>(lines.size()) >= kMaxElementLines) return false;
    for (int k = 0; k < static_cast<int>(lines.size()); ++k) {
        if (std::abs(lines[k].normal.dot(normal)) / n <= kRecutCos) continue;
        // Along line k: only where it bounds part of the element (a stem that stopped in it).
        bool everywhere = true;
        for (int v : fragments_of(w, c)) everywhere = everywhere && (w.virtual_elements.mask[v] & bound_by(k));
        if (everywhere) return false;
    }
    return true;
}

bool crosses_near_its_cut(const World& w, int e, int k, double t) {
    const int c = w.cuts.cut_of_element[e];
    if (c < 0) return false;
    const int* ed = edge_nodes(w.elements.dim, k);
    const Vec3 &a = w.nodes.rest[w.elements.nodes[e][ed[0]]], &b = w.nodes.rest[w.elements.nodes[e][ed[1]]];
    CutLine first;
    for (const CutLine& l : lines_in(w, c, first)) {
        const double da = l.normal.dot(a - l.origin), db = l.normal.dot(b - l.origin);
        if ((da >= 0.0) != (db >= 0.0) && std::abs(da / (da - db) - t) <= kAlongFraction) return true;
    }
    return false;
}

double incision_cos(const World& w, const CutEvent& ev) { return w.elements.dim == 3 && ev.tool < 0 ? kScriptedRecutCos : kRecutCos; }

bool signed_by_other_incision(const World& w, int e, const Vec3& normal, double cos_limit) {
    const double n = normal.norm();
    if (!(n > 0.0) || w.enriched.sign.empty()) return false;
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) {
        const int j = w.elements.nodes[e][a];
        if (w.enriched.sign[j] != 0 && std::abs(w.enriched.sign_normal[j].dot(normal)) / n < cos_limit) return true;
    }
    return false;
}

bool event_line(const CutEvent& ev, const std::array<Vec3, 3>& X, CutLine& line) {
    std::array<double, 3> level{};
    std::vector<Vec3> points;
    for (int k = 0; k < 3; ++k) {
        level[k] = ev.level[k];
        const int i = kTriEdges[k][0], j = kTriEdges[k][1];
        const double li = ev.level[i], lj = ev.level[j];
        if ((li >= 0.0) == (lj >= 0.0)) continue;
        const double t = ev.edge_has_t[k] ? ev.edge_t[k] : li / (li - lj);
        points.push_back(X[i] + std::clamp(t, 0.0, 1.0) * (X[j] - X[i]));
    }
    if (points.size() < 2 || (points[1] - points[0]).norm() == 0.0) return false;
    line = line_through(points[0], points[1], X, level);
    return true;
}

int across_edge(const World& w, int e, int a, int b) {
    for (int p = w.incidence.offset[a]; p < w.incidence.offset[a + 1]; ++p) {
        const int f = w.incidence.entry[p] >> 2;
        if (f == e || f >= w.mesh_elements) continue;
        const auto& m = w.elements.nodes[f];
        if (m[0] == b || m[1] == b || m[2] == b) return f;
    }
    return -1;
}

namespace {

/// Where `tool`'s blade went into mesh triangle f through its edge (a, b), as a parameter from a,
/// while it is still inside f (CutState: f among its partly crossed elements, that edge crossed);
/// -1 if it is not.
double blade_entry(const World& w, int tool, int f, int a, int b) {
    const auto& blades = w.cut_state.blade;
    if (tool < 0 || tool >= static_cast<int>(blades.size())) return -1.0;
    const auto it = blades[tool].crossing.find(f);
    if (it == blades[tool].crossing.end()) return -1.0;
    bool from_a = true;
    const int k = local_edge_of(w, f, a, b, from_a);
    return k >= 0 && (it->second.mask >> k & 1) ? param_from(it->second.t[k], from_a) : -1.0;
}

/// Whether `tool`'s blade has crossed the edge (a, b) of mesh triangle f and is still inside f.
bool blade_entered_across(const World& w, int tool, int f, int a, int b) { return blade_entry(w, tool, f, a, b) >= 0.0; }

/// The point of edge (a, b) of cut triangle e (a parameter from a) where one of e's lines crosses
/// it nearest `t`, if within kJoinFraction of it; else t.
double line_point_near(const World& w, int e, int a, int b, double t) {
    const Vec3 &Xa = w.nodes.rest[a], &Xb = w.nodes.rest[b];
    double best = t, gap = kJoinFraction;
    for (const CutLine& l : lines_of(w, w.cuts.cut_of_element[e])) {
        const double la = l.normal.dot(Xa - l.origin), lb = l.normal.dot(Xb - l.origin);
        if ((la >= 0.0) == (lb >= 0.0)) continue;
        const double s = la / (la - lb);
        if (std::abs(s - t) <= gap) gap = std::abs(s - t), best = s;
    }
    return best;
}

/// Whether rest point x is a corner of a fragment of cut triangle f (cut c): where one of f's
/// lines bounds material, not where the line runs on through a fragment it does not divide.
bool fragment_corner(const World& w, int f, int c, const Vec3& x, double tolerance) {
    const std::vector<CutLine>& lines = w.cuts.lines[c];
    const std::array<Vec3, 3> X = corners(w, f);
    for (int v : fragments_of(w, c))
        for (const Vec3& q : fragment_polygon(X, lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v]))
            if ((q - x).norm() <= tolerance) return true;
    return false;
}

/// Of the points where cracks already cross mesh edge (a, b) of a triangle mesh (a first cut's
/// points, and where a further line bounds a fragment at the edge), the parameter from a nearest
/// t; -1 if none. An edge two incisions cross holds a point of each.
double crack_point_near(const World& w, int a, int b, double t) {
    const Vec3 &Xa = w.nodes.rest[a], &Xb = w.nodes.rest[b];
    const double length2 = (Xb - Xa).squaredNorm();
    double best = -1.0;
    const auto take = [&](double s) {
        if (s > 0.0 && s < 1.0 && (best < 0.0 || std::abs(s - t) < std::abs(best - t))) best = s;
    };
    for (int p = w.incidence.offset[a]; p < w.incidence.offset[a + 1]; ++p) {
        const int f = w.incidence.entry[p] >> 2;
        const int c = f < w.mesh_elements ? w.cuts.cut_of_element[f] : -1;
        bool from_a = true;
        const int edge = c < 0 ? -1 : local_edge_of(w, f, a, b, from_a);
        if (edge < 0) continue;
        for (int k = 0; k < 4 && w.cuts.point_edge[c][k] >= 0; ++k)
            if (w.cuts.point_edge[c][k] == edge) take((w.cuts.points[c][k] - Xa).dot(Xb - Xa) / length2);
        const std::vector<CutLine>& lines = w.cuts.lines[c];
        for (size_t l = 1; l < lines.size(); ++l) {
            const double la = lines[l].normal.dot(Xa - lines[l].origin), lb = lines[l].normal.dot(Xb - lines[l].origin);
            if ((la >= 0.0) == (lb >= 0.0)) continue;
            const double s = la / (la - lb);
            if (fragment_corner(w, f, c, Xa + s * (Xb - Xa), 1e-9 * std::sqrt(length2))) take(s);
        }
    }
    return best;
}

}  // namespace

namespace {

/// Where a cut of one incision with `normal` (rest; within kRecutCos of it) already crosses mesh
/// edge (a, b) of a tetrahedral mesh: a first cut's point or a further plane's, in an element around
/// a; of several (two incisions of like direction cross the edge), the one nearest `own` (the
/// event's own crossing); the parameter from a, -1 if none.
double incision_edge_param(const World& w, int a, int b, const Vec3& normal, double own) {
    double best = -1.0;
    for (int p = w.incidence.offset[a]; p < w.incidence.offset[a + 1]; ++p) {
        const int f = w.incidence.entry[p] >> 2;
        const int c = f < w.mesh_elements ? w.cuts.cut_of_element[f] : -1;
        if (c < 0) continue;
        bool from_a = true;
        const int k = local_edge_of(w, f, a, b, from_a);
        if (k < 0) continue;
        CutLine first;
        const std::span<const CutLine> lines = lines_in(w, c, first);
        for (size_t l = 0; l < lines.size(); ++l) {
            const double stored = line_edge_params(w, c, l)[k];
            const double t = param_from(stored, from_a);
            if (stored >= 0.0 && std::abs(lines[l].normal.dot(normal)) > kRecutCos && (best < 0.0 || std::abs(t - own) < std::abs(best - own)))
                best = t;
        }
    }
    return best;
}

/// A cut through four edges of a tetrahedron (`order`: those whose points are fixed first): the
/// last point moves onto the plane through the other three, so the cut is one plane through its
/// points. A blade's crossings of one element are measured over several steps while the tissue
/// moves, so at rest its four points are not coplanar (up to 7e-4 of an edge on the default skin),
/// and a plane fitted through them misses the fourth: the surfaces of two neighbours then meet it at
/// different places. Left as it is where the plane does not cross the edge inside it.
void put_fourth_on_plane(CutEvent& ev, const std::array<Vec3, 4>& X, const std::array<int, 6>& order) {
    std::array<Vec3, 4> p;
    for (int q = 0; q < 4; ++q) {
        const int k = order[q], i = kTetEdges[k][0], j = kTetEdges[k][1];
        const double t = ev.edge_has_t[k] ? ev.edge_t[k] : ev.level[i] / (ev.level[i] - ev.level[j]);
        p[q] = X[i] + t * (X[j] - X[i]);
    }
    const Vec3 normal = (p[1] - p[0]).cross(p[2] - p[0]);
    const int k = order[3], i = kTetEdges[k][0], j = kTetEdges[k][1];
    const double along = normal.dot(X[j] - X[i]);
    if (!(std::abs(along) > 0.0)) return;
    const double t = normal.dot(p[0] - X[i]) / along;
    if (t > 0.0 && t < 1.0) ev.edge_t[k] = t, ev.edge_has_t[k] = 1;
}

/// join_earlier_points in 3D, for a scalpel's event: each edge it crosses takes the point its own
/// incision already put there in a neighbour (its crossings were measured alike, but an edge the
/// blade's sweep did not reach takes each element's plane through its three crossings, and two
/// neighbours' planes differ on their common face); a cut through four edges is then made planar
/// (put_fourth_on_plane).
void join_incision_points(const World& w, CutEvent& ev) {
    CutLine plane;
    if (!event_cut_line(w, ev, plane)) return;
    const auto& n = w.elements.nodes[ev.element];
    std::array<int, 6> order{};  // the crossed edges, those with a neighbour's point first
    std::array<bool, 6> crossed{}, joined{};
    for (int k = 0; k < 6; ++k) {
        const int i = kTetEdges[k][0], j = kTetEdges[k][1];
        crossed[k] = (ev.level[i] >= 0.0) != (ev.level[j] >= 0.0);
        const double own = ev.edge_has_t[k] ? ev.edge_t[k] : ev.level[i] / (ev.level[i] - ev.level[j]);
        const double t = crossed[k] ? incision_edge_param(w, n[i], n[j], plane.normal, own) : -1.0;
        joined[k] = t > 0.0 && t < 1.0;
        if (joined[k]) ev.edge_t[k] = t, ev.edge_has_t[k] = 1;
    }
    int m = 0, shared = 0;
    for (int pass = 0; pass < 2; ++pass)
        for (int k = 0; k < 6; ++k)
            if (crossed[k] && joined[k] == (pass == 0)) order[m++] = k, shared += joined[k];
    if (m == 4 && shared < 4) put_fourth_on_plane(ev, tet_corners(w, ev.element), order);
}

}  // namespace

void join_earlier_points(const World& w, CutEvent& ev) {
    const int e = ev.element;
    if (e < 0 || e >= w.mesh_elements || (ev.bounded && w.elements.dim == 2)) return;
    if (w.elements.dim == 3) {  // a stem too: its crossings are its incision's in the elements beside
        if (ev.tool >= 0) join_incision_points(w, ev);
        return;
    }
    const auto& n = w.elements.nodes[e];
    const auto& cut = w.cuts.cut_of_element;
    for (int k = 0; k < 3; ++k) {
        const int i = kTriEdges[k][0], j = kTriEdges[k][1];
        const double li = ev.level[i], lj = ev.level[j];
        if ((li >= 0.0) == (lj >= 0.0)) continue;
        const double t = ev.edge_has_t[k] ? ev.edge_t[k] : li / (li - lj);
        const int f = across_edge(w, e, n[i], n[j]);
        // The blade comes back out of the element across through the edge it went in by, away
        // from where it went in (a path that dips into an element already cut, and leaves it where
        // another wound meets the edge): the crack runs along the edge between, from the point
        // where the blade went in (or e's line there). Joined to the other wound instead, the
        // crack would leave the edge's part between the two points, and the material of the
        // element across along it, joining both sides of the blade's path (a loop's lens kept).
        const double entry = cut[e] >= 0 && f >= 0 && ev.tool >= 0 ? blade_entry(w, ev.tool, f, n[i], n[j]) : -1.0;
        if (entry >= 0.0 && std::abs(entry - t) > kJoinFraction) {
            ev.edge_t[k] = line_point_near(w, e, n[i], n[j], entry), ev.edge_has_t[k] = 1;
            continue;
        }
        // The element's own crack ends on this edge, where the same blade went into the uncut
        // element across, and the blade comes back out through it: the crack runs along the edge
        // between (a path that grazes a mesh line dips into the element beyond by a hair).
        const bool back = cut[e] >= 0 && f >= 0 && cut[f] < 0 && ev.tool >= 0 && w.cuts.tool[cut[e]] == ev.tool &&
                          blade_entered_across(w, ev.tool, f, n[i], n[j]);
        // Else, for a blade, the earlier point nearest: an edge a cross-cut and a loop's first pass
        // both cross holds two, and the closing pass meets the one it retraces (its crossings are
        // measured on moving tissue; a scripted cut, drawn at rest, keeps the first point's rule).
        const double earlier = back || ev.tool < 0 ? crack_edge_param(w, n[i], n[j]) : crack_point_near(w, n[i], n[j], t);
        if (earlier <= 0.0 || earlier >= 1.0 || earlier == t) continue;
        if (!back && std::abs(earlier - t) > kJoinFraction) continue;
        ev.edge_t[k] = earlier, ev.edge_has_t[k] = 1;
    }
}

namespace {

/// How a further cut divides one fragment: the measure (area, volume) of its parts on the line's
/// sides 1 and 0; both 0 where it does not cross it.
struct Parts {
    double one = 0.0, zero = 0.0;
};

/// Index of the line among `before` that `line` is (within a degree and a thousandth of the
/// element's size: the path's map to rest changes a little as the element deforms between the
/// cuts), -1 if none; `line` becomes that line.
int same_line(const std::vector<CutLine>& before, CutLine& line, double size) {
    for (int k = 0; k < static_cast<int>(before.size()); ++k)
        if (std::abs(before[k].normal.dot(line.normal)) > kSameLineCos &&
            std::abs(before[k].normal.dot(line.origin - before[k].origin)) < 1e-3 * size) {
            line = before[k];
            return k;
        }
    return -1;
}

/// Whether `line` crosses an edge of triangle e (rest corners X) that event ev crosses at a point an
/// earlier crack put there (crack_point_near: a neighbour's or one of e's own) more than
/// kEdgeOverlap2d of the edge from that point (or misses the edge).
bool misses_earlier_point(const World& w, int e, const CutEvent& ev, const std::array<Vec3, 3>& X, const CutLine& line) {
    const auto& n = w.elements.nodes[e];
    for (int k = 0; k < 3; ++k) {
        const int i = kTriEdges[k][0], j = kTriEdges[k][1];
        if (!ev.edge_has_t[k] || (ev.level[i] >= 0.0) == (ev.level[j] >= 0.0)) continue;
        const double t = ev.edge_t[k];
        if (std::abs(crack_point_near(w, n[i], n[j], t) - t) > 1e-12) continue;  // a point of its own
        const double a = line.normal.dot(X[i] - line.origin), b = line.normal.dot(X[j] - line.origin);
        if ((a >= 0.0) == (b >= 0.0) || std::abs(a / (a - b) - t) > kEdgeOverlap2d) return true;
    }
    return false;
}

/// A part of a fragment below this fraction of its element's volume is round-off of a plane through
/// a node or along a face, not a sliver [-].
constexpr double kSliverRoundOff = 1e-12;

/// Divides cut element c's fragments `frags` by `line` (line `same` of its own, or a new one) into
/// their parts `parts` of the element's `measure`: the part on side 1 stays the old virtual
/// element (new weight), a new one takes the rest. False (nothing changed) if it divides none.
bool divide_fragments(World& w, int c, const std::vector<int>& frags, const std::vector<Parts>& parts,
                      const CutLine& line, int same, double measure, const std::array<double, 6>* edge_t = nullptr) {
    // Every fragment the line (plane) crosses is divided, a sliver too (its weight held at
    // kMinSideFraction, as an element cut once near a node): left whole, its sliver across the line
    // would join the material there at the edges (faces) it shares with the neighbours the line
    // divided. In 3D a bridge at an X's crossing, where both cuts cross an edge a few micrometres
    // apart; in 2D a loop's pass 2.5 um beside a node, whose corner in the element it crossed there
    // (already cut by the loop's other pass) held 6e-7 of it and kept the lens joined.
    const double least = kSliverRoundOff * measure;
    const auto divided = [&](const Parts& p) { return p.one >= least && p.zero >= least; };
    if (std::none_of(parts.begin(), parts.end(), divided)) return false;
    const int e = w.cuts.element[c];
    ensure_lines(w, c);
    const int k = same >= 0 ? same : static_cast<int>(w.cuts.lines[c].size());
    if (same < 0) w.cuts.lines[c].push_back(line);
    if (same < 0 && edge_t) w.cuts.line_edge_t[c].push_back(*edge_t);
    const uint32_t bit = 1u << k;
    VirtualElements& ve = w.virtual_elements;
    for (size_t f = 0; f < frags.size(); ++f) {
        const int v = frags[f];
        if (!divided(parts[f])) continue;
        const int fe = ve.element[v];
        w.elements.weight[fe] = std::max(parts[f].one / measure, kMinSideFraction);
        ve.mask[v] |= bit | bound_by(k);
        w.cuts.fragments[c].push_back(ve.count());
        ve.parent.push_back(e);
        ve.side.push_back(ve.side[v]);
        ve.mask.push_back(ve.mask[v] & ~bit);
        ve.element.push_back(append_element_copy(w.elements, fe, std::max(parts[f].zero / measure, kMinSideFraction)));
    }
    return true;
}

/// record_recut in 3D: a plane through the tetrahedron divides each fragment it leaves parts of on
/// both sides (a cut that ends inside an element is not made there: the cutters ask only for
/// elements crossed in full).
bool record_recut_3d(World& w, const CutEvent& ev, int c) {
    const std::array<Vec3, 4> X = tet_corners(w, ev.element);
    CutLine plane;
    if (!event_plane(ev, X, plane)) return false;
    const std::vector<CutLine> before = lines_of(w, c);
    const int same = same_line(before, plane, longest_edge(X));
    if (same < 0 && static_cast<int>(before.size()) >= kMaxElementLines) return false;
    std::vector<CutLine> planes = before;
    if (same < 0) planes.push_back(plane);
    const int k = same >= 0 ? same : static_cast<int>(before.size()), n = static_cast<int>(planes.size());
    const std::span<const int> now = fragments_of(w, c);
    const std::vector<int> frags(now.begin(), now.end());
    std::vector<Parts> parts;
    for (int v : frags) {
        const uint32_t mask = w.virtual_elements.mask[v];
        if (same >= 0 && (mask & bound_by(same))) {
            parts.push_back({});
            continue;
        }
        const uint32_t with = mask | bound_by(k), above = with | (1u << k), below = with & ~(1u << k);
        double above_volume = 0.0;
        if (ev.bounded) {  // a stem: only a fragment whose section lies ahead of its start (stem_3d.h)
            const std::vector<FragmentFace> faces = fragment_faces(X, planes.data(), n, above);
            std::vector<Vec3> section;
            for (const FragmentFace& f : faces)
                if (f.plane == k) section.insert(section.end(), f.polygon.begin(), f.polygon.end());
            if (!stem_covers(ev, section, longest_edge(X))) {
                parts.push_back({});
                continue;
            }
            above_volume = polyhedron_volume(faces);  // fragment_volume's bits, its faces made already
        } else {
            above_volume = fragment_volume(X, planes.data(), n, above);
        }
        parts.push_back({above_volume, fragment_volume(X, planes.data(), n, below)});
    }
    const double volume = std::abs((X[1] - X[0]).cross(X[2] - X[0]).dot(X[3] - X[0])) / 6.0;
    std::array<double, 6> edge_t;  // the event's own crossings of the edges
    edge_t.fill(-1.0);
    for (int e = 0; e < 6; ++e) {
        const double li = ev.level[kTetEdges[e][0]], lj = ev.level[kTetEdges[e][1]];
        if ((li >= 0.0) != (lj >= 0.0)) edge_t[e] = std::clamp(ev.edge_has_t[e] ? ev.edge_t[e] : li / (li - lj), 0.0, 1.0);
    }
    return divide_fragments(w, c, frags, parts, plane, same, volume, &edge_t);
}

}  // namespace

bool event_plane(const CutEvent& ev, const std::array<Vec3, 4>& X, CutLine& plane) {
    std::array<double, 4> level{};
    std::array<Vec3, 6> points;
    int np = 0;
    for (int a = 0; a < 4; ++a) level[a] = ev.level[a];
    for (int k = 0; k < 6; ++k) {
        const int i = kTetEdges[k][0], j = kTetEdges[k][1];
        const double li = ev.level[i], lj = ev.level[j];
        if ((li >= 0.0) == (lj >= 0.0)) continue;
        const double t = ev.edge_has_t[k] ? ev.edge_t[k] : li / (li - lj);
        points[np++] = X[i] + std::clamp(t, 0.0, 1.0) * (X[j] - X[i]);
    }
    if (np < 3) return false;
    plane = plane_through(points.data(), np, X, level);
    return plane.normal.squaredNorm() > 0.0;
}

bool event_cut_line(const World& w, const CutEvent& ev, CutLine& line) {
    if (w.elements.dim == 3) return event_plane(ev, tet_corners(w, ev.element), line);
    return event_line(ev, corners(w, ev.element), line);
}

bool record_recut(World& w, const CutEvent& ev) {
    const int e = ev.element;
    if (e < 0 || e >= w.mesh_elements) return false;
    const int c = w.cuts.cut_of_element[e];
    if (c < 0) return false;
    if (w.elements.dim == 3) return record_recut_3d(w, ev, c);
    const std::array<Vec3, 3> X = corners(w, e);
    CutLine line;
    if (!event_line(ev, X, line)) return false;
    const double size = longest_edge(X);
    const std::vector<CutLine> before = lines_of(w, c);
    // One of its lines again (a stem that stopped on it goes on): the fragments it does not bound
    // yet may be divided by it, and no line is added.
    const CutLine own = line;
    int same = same_line(before, line, size);
    if (same >= 0 && static_cast<int>(before.size()) < kMaxElementLines && misses_earlier_point(w, e, ev, X, line))
        same = -1, line = own;  // the loop's closing pass of seed 2's trajectory 628: 13 um from the point beside
    if (same < 0 && static_cast<int>(before.size()) >= kMaxElementLines) return false;
    // Which fragments the line divides: each part's area, decided before anything changes.
    const std::span<const int> now = fragments_of(w, c);
    const std::vector<int> frags(now.begin(), now.end());  // the fragments before this line; it adds more
    const double area = polygon_area({X.begin(), X.end()});
    const int n = static_cast<int>(before.size());
    // The line as a long segment a -> b through the element, and the part of it the cut covers.
    const Vec3 along(-line.normal.y(), line.normal.x(), 0.0);
    const Vec3 a = line.origin - 2.0 * size * along, b = line.origin + 2.0 * size * along;
    double from = 0.0, to = 1.0;
    if (ev.bounded) {
        from = (ev.extent[0] - a).dot(along) / (4.0 * size), to = (ev.extent[1] - a).dot(along) / (4.0 * size);
        if (from > to) std::swap(from, to);
    }
    const double slack = 1e-9;  // of the long segment: round-off of a cut ending on an earlier line
    std::vector<Parts> parts;
    for (int v : frags) {
        const uint32_t mask = w.virtual_elements.mask[v];
        const std::vector<Vec3> poly = fragment_polygon(X, before.data(), n, mask);
        const std::array<double, 2> chord = segment_in_polygon(a, b, poly);
        const bool across = chord[0] >= from - slack && chord[1] <= to + slack &&  // crossed from side to side
                            (same < 0 || !(mask & bound_by(same)));
        parts.push_back({across ? polygon_area(clip_to_side(poly, line, true)) : 0.0,
                         across ? polygon_area(clip_to_side(poly, line, false)) : 0.0});
    }
    return divide_fragments(w, c, frags, parts, line, same, area);
}

}  // namespace xcut
