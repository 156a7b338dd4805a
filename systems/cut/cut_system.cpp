#include "systems/cut/cut_system.h"

#include <algorithm>
#include <cmath>

#include "components/cut_elements.h"
#include "engine/parallel.h"
#include "engine/quadratic_setup.h"
#include "systems/cut/edge_geometry.h"
#include "systems/cut/material_anchor.h"
#include "systems/cut/node_sides.h"
#include "systems/cut/quad_reach.h"
#include "systems/cut/recut.h"
#include "systems/cut/stem_2d.h"
#include "systems/cut/stem_3d.h"
#include "systems/cut/skin_flap.h"
#include "systems/kernels/intersection.h"
#include "systems/kernels/blade_pose.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/xfem_queries.h"

namespace xcut {

MeshView mesh_view(const World& w) { return {&w.elements, &w.nodes.position, w.mesh_elements, w.mesh_nodes}; }

namespace {

/// Side of x relative to the crossing surface: +1 or -1 (0 counts as +1, the fixed tie-break).
int side_of(const Vec3& x, const Vec3& point, const Vec3& normal) {
    return (x - point).dot(normal) >= 0.0 ? 1 : -1;
}

/// The unit normal of the blade over the element's crossed edges (their quads' normals, each
/// turned to the first's side).
Vec3 crossing_normal(const ElementCrossings& c) {
    Vec3 sum = Vec3::Zero(), first = Vec3::Zero();
    for (int k = 0; k < 6; ++k) {
        if (!(c.mask >> k & 1)) continue;
        if (first.isZero()) first = c.normal[k];
        sum += c.normal[k].dot(first) < 0.0 ? Vec3(-c.normal[k]) : c.normal[k];
    }
    return sum.norm() > 0.0 ? Vec3(sum.normalized()) : sum;
}

/// The edges (bit k) whose nodes the 2-colouring `pattern` parts (bit a - 1: node a's colour; node 0
/// has colour 0).
int parted_edges(int dim, int pattern) {
    int differ = 0;
    for (int k = 0; k < edge_count(dim); ++k) {
        const int* ed = edge_nodes(dim, k);
        const int ci = ed[0] == 0 ? 0 : (pattern >> (ed[0] - 1)) & 1;
        const int cj = ed[1] == 0 ? 0 : (pattern >> (ed[1] - 1)) & 1;
        if (ci != cj) differ |= 1 << k;
    }
    return differ;
}

/// A triangle crossed on all three edges (2D): a path that clipped a corner and came back, grazing
/// a mesh line. The colouring whose cut joins the two crossings farthest apart; the third, beside
/// one of them at the clipped corner, is left.
int widest_pair(const World& w, int e, const ElementCrossings& c) {
    int best = -1;
    double widest = -1.0;
    for (int pattern = 1; pattern < 4; ++pattern) {
        const int differ = parted_edges(2, pattern), k0 = __builtin_ctz(differ), k1 = 31 - __builtin_clz(differ);
        const double apart = (edge_point(w, e, k0, c.t[k0]) - edge_point(w, e, k1, c.t[k1])).norm();
        if (apart > widest) widest = apart, best = pattern;
    }
    return best;
}

/// Builds the split of an element from its crossed edges: node signs (the 2-colouring whose
/// differing edges contain the crossed ones with the fewest extra, oriented by the quad's normal or
/// by signs already fixed) and the crossing parameter of every differing edge. False if no
/// consistent split exists (a curved sweep crossing all edges of one face).
bool make_event(const World& w, int e, const ElementCrossings& crossings, CutEvent& ev) {
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element(), ne = edge_count(dim);
    ElementCrossings c = crossings;
    int best = -1, best_extra = 99;
    for (int pattern = 1; pattern < (1 << (npe - 1)); ++pattern) {  // node 0 keeps colour 0
        const int differ = parted_edges(dim, pattern);
        if ((differ & c.mask) != c.mask) continue;
        const int extra = __builtin_popcount(differ & ~c.mask);
        if (extra < best_extra) best_extra = extra, best = pattern;
    }
    if (best < 0 && dim == 2 && recut_allowed(w) && c.mask == 7)  // where elements are cut again
        best = widest_pair(w, e, c), c.mask = static_cast<uint8_t>(parted_edges(dim, best));
    if (best < 0) return false;
    auto colour = [&](int a) { return a == 0 ? 0 : (best >> (a - 1)) & 1; };
    // Orientation: signs already fixed win (not another incision's, where elements are cut again:
    // systems/cut/recut.h); else the side of the first crossed edge's first node.
    int colour0_sign = 0;
    const auto& sign = w.enriched.sign;
    const bool own = recut_allowed(w) && signed_by_other_incision(w, e, crossing_normal(c));
    for (int a = 0; a < npe && !own; ++a) {
        const int s = sign.empty() ? 0 : sign[el.nodes[e][a]];
        if (s == 0) continue;
        const int implied = colour(a) == 0 ? s : -s;
        if (colour0_sign != 0 && implied != colour0_sign) {  // contradicts fixed signs
            if (!recut_allowed(w)) return false;
            break;  // where elements are cut again its line decides (record_cut: sides_disagree)
        }
        colour0_sign = implied;
    }
    const Vec3* x = w.nodes.position.data();
    int first = 0;
    while (!(c.mask >> first & 1)) ++first;
    const int* fe = edge_nodes(dim, first);
    const Vec3 p = edge_point(w, e, first, c.t[first]);
    if (colour0_sign == 0) {
        const int s = side_of(x[el.nodes[e][fe[0]]], p, c.normal[first]);
        colour0_sign = colour(fe[0]) == 0 ? s : -s;
    }
    ev = CutEvent{};
    ev.element = e;
    for (int a = 0; a < npe; ++a) ev.level[a] = colour(a) == 0 ? colour0_sign : -colour0_sign;
    // Parameters: measured on crossed edges; on an inferred edge, from the plane through the
    // measured crossing points (exact for a planar cut).
    std::vector<Vec3> pts;
    for (int k = 0; k < ne; ++k) {
        if (!(c.mask >> k & 1)) continue;
        ev.edge_t[k] = c.t[k];
        ev.edge_has_t[k] = 1;
        pts.push_back(edge_point(w, e, k, c.t[k]));
    }
    Vec3 n = c.normal[first];
    if (dim == 3 && pts.size() >= 3) {
        const Vec3 m = (pts[1] - pts[0]).cross(pts[2] - pts[0]);
        if (m.norm() > 0.0) n = m.normalized();
    }
    for (int k = 0; k < ne; ++k) {
        const int* ed = edge_nodes(dim, k);
        if ((c.mask >> k & 1) || colour(ed[0]) == colour(ed[1])) continue;
        ev.edge_t[k] = plane_edge_param(w, e, k, pts[0], n);
        ev.edge_has_t[k] = 1;
    }
    return true;
}

/// Progressive front: a node whose side is not fixed yet and lies closer than this fraction of the
/// element's shortest edge to the extended plane keeps the element waiting for the blade [-].
constexpr double kTipNodeMargin = 0.1;

/// Progressive front (docs/xfem.md): the split of an element the blade has entered but not fully
/// crossed, on the blade's plane extended through it: through the first crossing, normal to the
/// plane of three crossings when there are three, else to the quad. Node levels are signed
/// distances to that plane, so the uncrossed edges' parameters follow from them. False when a node
/// sign already fixed disagrees with the plane, or a crossed edge then has both nodes on one side
/// (a curved sweep): the element waits for its next crossing, and at worst is split once fully
/// crossed, as on the semi-progressive front. (make_event's colouring, the fewest split edges
/// besides the crossed ones, need not be the plane's while only one or two edges are crossed.)
bool tip_event(const World& w, int e, const ElementCrossings& c, CutEvent& ev) {
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element(), ne = edge_count(dim);
    const Vec3* x = w.nodes.position.data();
    std::vector<Vec3> pts;
    int first = -1;
    for (int k = 0; k < ne; ++k) {
        if (!(c.mask >> k & 1)) continue;
        if (first < 0) first = k;
        pts.push_back(edge_point(w, e, k, c.t[k]));
    }
    if (first < 0) return false;
    Vec3 n = c.normal[first];
    if (dim == 3 && pts.size() >= 3) {
        const Vec3 m = (pts[1] - pts[0]).cross(pts[2] - pts[0]);
        if (m.norm() > 0.0) n = m.dot(n) >= 0.0 ? m : Vec3(-m);
    }
    if (!(n.norm() > 0.0)) return false;
    n.normalize();
    const auto& sign = w.enriched.sign;
    std::array<int, 4> H{};
    ev = CutEvent{};
    ev.element = e;
    const double shortest = shortest_edge(el, x, e);
    for (int a = 0; a < npe; ++a) {
        ev.level[a] = (x[el.nodes[e][a]] - pts[0]).dot(n);
        H[a] = ev.level[a] >= 0.0 ? 1 : -1;
        const int fixed = sign.empty() ? 0 : sign[el.nodes[e][a]];
        if (fixed != 0 && fixed != H[a]) return false;
        // A node this close to the extended plane would get its side from a guess: wait for the blade.
        if (fixed == 0 && std::abs(ev.level[a]) < kTipNodeMargin * shortest) return false;
    }
    for (int k = 0; k < ne; ++k) {
        const int* ed = edge_nodes(dim, k);
        if (!(c.mask >> k & 1)) continue;
        if (H[ed[0]] == H[ed[1]]) return false;
        ev.edge_t[k] = c.t[k];
        ev.edge_has_t[k] = 1;
    }
    return true;
}

void remove_from_list(BladeCut& bc, int e, int list) {
    if (list < 1) return;
    auto& l = bc.lists[list - 1];
    l.erase(std::remove(l.begin(), l.end(), e), l.end());
}

/// Where local edge k of element e crosses the quad (its parameter along the edge), and which of
/// the quad's triangles it crosses (`tri`). A quadratic element's edge is the curve through its
/// mid-edge node; its parameter is the rest edge's, as a straight edge's is. `sides`: the nodes'
/// orientations against the triangles of quad number `which` of the call (the same bits as without).
std::optional<double> edge_crossing(const World& w, int e, int k, const CutQuad& q, int& tri,
                                    NodeSides* sides = nullptr, int which = 0) {
    const int dim = w.elements.dim;
    const int* ed = edge_nodes(dim, k);
    const Vec3& a = w.nodes.position[w.elements.nodes[e][ed[0]]];
    const Vec3& b = w.nodes.position[w.elements.nodes[e][ed[1]]];
    tri = 0;
    if (dim != 3) return segment_segment_2d(a, b, q.corner[0], q.corner[3]);
    if (const int m = mid_edge_node(w, e, ed[0], ed[1]); m >= 0) {
        const Vec3& pm = w.nodes.position[m];
        std::optional<double> s = quadratic_edge_triangle(a, pm, b, q.corner[0], q.corner[1], q.corner[2]);
        if (!s) s = quadratic_edge_triangle(a, pm, b, q.corner[0], q.corner[2], q.corner[3]), tri = 1;
        return s;
    }
    if (sides) {
        const int i = w.elements.nodes[e][ed[0]], j = w.elements.nodes[e][ed[1]];
        std::optional<double> t =
            segment_triangle(sides->at(i, which, 0), sides->at(j, which, 0), a, b, q.corner[0], q.corner[1], q.corner[2]);
        if (!t)
            t = segment_triangle(sides->at(i, which, 1), sides->at(j, which, 1), a, b, q.corner[0], q.corner[2], q.corner[3]),
            tri = 1;
        return t;
    }
    std::optional<double> t = segment_triangle(a, b, q.corner[0], q.corner[1], q.corner[2]);
    if (!t) t = segment_triangle(a, b, q.corner[0], q.corner[2], q.corner[3]), tri = 1;
    return t;
}

/// The quad's two triangles' normals (2D: the swept segment's normal) [m^2; 2D m].
std::array<Vec3, 2> quad_normals(int dim, const CutQuad& q) {
    if (dim != 3) {
        const Vec3 d = q.corner[3] - q.corner[0];
        return {Vec3(-d.y(), d.x(), 0.0), Vec3(-d.y(), d.x(), 0.0)};
    }
    return {(q.corner[1] - q.corner[0]).cross(q.corner[2] - q.corner[0]),
            (q.corner[2] - q.corner[0]).cross(q.corner[3] - q.corner[0])};
}

/// A blade in cut element e (2D) through edge k alone that crosses that edge again at t away from
/// where it came in (more than kAlongFraction of the edge), having turned at `turn` (the quad's
/// start, current position) beside one of e's lines (within kJoinFraction of its longest edge): it
/// dipped into the element and back out, as a loop closing beside its first pass does in the sliver
/// between that pass and a mesh line (loop stress trajectories 275, 845). Where it turned is kept
/// (ElementCrossings::turn): crossed nowhere else by the time the blade leaves the element, it is
/// cut from where the blade came in to there (drop_left, end_stems), not left joined across the dip.
void note_dip(const World& w, int e, ElementCrossings& c, int k, double t, const Vec3& turn) {
    const auto& cut = w.cuts.cut_of_element;
    if (w.elements.dim != 2 || !recut_allowed(w) || cut.empty() || cut[e] < 0 || c.split || c.mask != (1u << k) ||
        !(std::abs(t - c.t[k]) > kAlongFraction))
        return;
    const MaterialPoint m = material_in(w, e, turn);
    if (m.element < 0) return;
    const std::array<Vec3, 3> X = corners(w, e);
    const Vec3 at = material_rest(w, m);
    for (const CutLine& l : lines_of(w, cut[e]))
        if (std::abs(l.normal.dot(at - l.origin)) < kJoinFraction * longest_edge(X)) c.turn = m;
}

/// Tests the candidate's edges against the quads (the edge's sweep, and the blade's face when it
/// has one); returns how many new distinct edges it crossed. `beside`: a cut element the blade
/// passes along its cut, whose crossings count only if one of them is away from its cut (recut.h);
/// those near it are kept until one is (BladeCut::near).
int test_element(World& w, BladeCut& bc, int e, const std::vector<const CutQuad*>& quads,
                 const std::vector<std::array<Vec3, 2>>& normals, bool beside, NodeSides& sides) {
    const int edges = edge_count(w.elements.dim);
    std::array<std::optional<double>, 6> t{};
    std::array<const Vec3*, 6> normal{};
    bool away = !beside;
    for (int k = 0; k < edges; ++k) {
        int tri = 0;
        size_t which = 0;
        for (; which < quads.size() && !t[k]; ++which) t[k] = edge_crossing(w, e, k, *quads[which], tri, &sides, static_cast<int>(which));
        if (t[k]) normal[k] = &normals[which - 1][tri], away = away || !crosses_near_its_cut(w, e, k, *t[k]);
    }
    const auto kept = bc.near.empty() ? bc.near.end() : bc.near.find(e);  // most quads keep none
    if (!away) {  // near the cut alone: kept, the first crossing of each edge, until one is away
        if (std::none_of(t.begin(), t.end(), [](const auto& x) { return x.has_value(); })) return 0;
        ElementCrossings& n = kept != bc.near.end() ? kept->second : bc.near[e];
        for (int k = 0; k < edges; ++k)
            if (t[k] && !(n.mask >> k & 1)) n.mask |= uint8_t(1u << k), n.t[k] = *t[k], n.normal[k] = *normal[k];
        return 0;
    }
    if (kept != bc.near.end())  // away from the cut: the blade's crossings near it before count too
        for (int k = 0; k < edges; ++k)
            if (!t[k] && (kept->second.mask >> k & 1)) t[k] = kept->second.t[k], normal[k] = &kept->second.normal[k];
    int found = 0;
    for (int k = 0; k < edges; ++k) {
        if (!t[k]) continue;
        auto it = bc.crossing.find(e);
        if (it == bc.crossing.end()) {
            ElementCrossings fresh;
            fresh.first_time = w.time;
            fresh.first_wall = wall_seconds();
            it = bc.crossing.emplace(e, fresh).first;
        }
        ElementCrossings& c = it->second;
        if (c.mask >> k & 1) {  // this edge already counted: a trembling blade, or a dip
            note_dip(w, e, c, k, *t[k], quads[0]->corner[0]);
            continue;
        }
        c.mask |= uint8_t(1u << k);
        c.t[k] = *t[k];
        c.normal[k] = *normal[k];
        ++found;
    }
    if (kept != bc.near.end()) bc.near.erase(kept);  // counted now
    return found;
}


/// Whether quad q crosses one of element e's edges.
bool quad_crosses_element(const World& w, int e, const CutQuad& q) {
    for (int k = 0; k < edge_count(w.elements.dim); ++k) {
        int tri = 0;
        if (edge_crossing(w, e, k, q, tri)) return true;
    }
    return false;
}

/// An element already split that the quad of `tool` crosses along another plane: counted once per
/// tool (CutState::recut_ignored; the end of the run says so).
void note_recut(World& w, int e, const CutQuad& q, const Vec3& quad_normal, int tool) {
    CutState& cs = w.cut_state;
    const auto it = cs.split_normal.find(e);
    const double n = quad_normal.norm();
    if (it == cs.split_normal.end() || n == 0.0 || std::abs(it->second.dot(quad_normal)) / n > kRecutCos) return;
    // Cut again along the quad already (the quad passes along that cut; lines at rest).
    const int c = w.cuts.cut_of_element.empty() ? -1 : w.cuts.cut_of_element[e];
    if (c >= 0 && !w.cuts.lines[c].empty())
        for (const CutLine& l : w.cuts.lines[c])
            if (std::abs(l.normal.dot(quad_normal)) / n > kRecutCos) return;
    if (!quad_crosses_element(w, e, q) || !cs.recut_seen.insert(int64_t(e) * 64 + tool).second) return;
    if (static_cast<int>(cs.recut_ignored.size()) <= tool) cs.recut_ignored.resize(tool + 1, 0);
    ++cs.recut_ignored[tool];
}

/// Queues the splits of the elements the last quad crossed and moves the others through the lists,
/// in element order (deterministic): an element fully crossed is split (make_event); on a
/// progressive front one the blade has only entered is split as a tip element (tip_event), and a
/// tip element's later crossings are queued as events for the enrichment. An element already cut
/// (2D) is cut again once fully crossed, or where the quad, starting inside it at `start`, leaves it
/// (the stem of a T: stem_event; in 3D, where the blade began inside it: stem_event_3d).
void split_or_list(World& w, BladeCut& bc, const std::vector<int>& crossed, int tool, const CutQuad& q) {
    CutState& cs = w.cut_state;
    const int need = w.elements.dim == 3 ? 3 : 2;
    for (int e : crossed) {
        ElementCrossings& c = bc.crossing.at(e);
        const int count = std::min(__builtin_popcount(c.mask), 3);
        const bool full = count >= need;
        if (!w.cuts.cut_of_element.empty() && w.cuts.cut_of_element[e] >= 0 && !c.split) {  // cut again, once fully crossed
            CutEvent ev;
            const auto began = bc.began_in.find(e);  // 3D: the element a stem starts in waits for it
            const bool stem = began != bc.began_in.end()
                                  ? stem_event_3d(w, e, began->second, q.corner[3], c, ev)
                                  : count == 1 && stem_event(w, e, __builtin_ctz(c.mask), c.t[__builtin_ctz(c.mask)], q.corner[0], ev);
            const bool whole = full && began == bc.began_in.end();
            if ((whole && make_event(w, e, c, ev)) || stem) {
                ev.again = true, ev.tool = tool;
                w.pending_cuts.push_back(ev);
                ++cs.elements_split;
            }
            if (whole || stem) {
                if (stem) bc.began_in.erase(e);
                remove_from_list(bc, e, c.list);
                bc.crossing.erase(e);
            } else if (count != c.list) {
                remove_from_list(bc, e, c.list);
                c.list = count;
                bc.lists[count - 1].push_back(e);
            }
            continue;
        }
        if (c.split) {  // a tip element already split: the enrichment learns which edges are crossed now
            CutEvent ev;
            ev.element = e;
            ev.crossed = full ? 0xFF : c.mask;
            w.pending_cuts.push_back(ev);
        } else if (full || cs.progressive) {
            CutEvent ev;
            const bool made = full ? make_event(w, e, c, ev) : tip_event(w, e, c, ev);
            if (made && lies_on_skin(w, e, ev)) {  // no incision: its crossings are forgotten, so a blade
                                                   // that goes deeper later crosses it anew
                if (static_cast<int>(cs.on_skin_ignored.size()) <= tool) cs.on_skin_ignored.resize(tool + 1, 0);
                cs.on_skin_ignored[tool] += cs.on_skin_seen.insert(int64_t(e) * 64 + tool).second;
                remove_from_list(bc, e, c.list);
                bc.crossing.erase(e);
                continue;
            }
            if (made) {
                ev.crossed = full ? 0xFF : c.mask;
                ev.tool = tool;
                ev.entered_time = c.first_time;
                ev.entered_wall = c.first_wall;
                w.pending_cuts.push_back(ev);
                if (cs.queued.empty()) cs.queued.assign(w.mesh_elements, 0);
                cs.queued[e] = 1;
                cs.split_normal[e] = crossing_normal(c);
                cs.delay_sim.push_back(w.time - c.first_time);
                cs.delay_wall.push_back(wall_seconds() - c.first_wall);
                ++cs.elements_split;
                c.split = true;
                if (e == bc.start_element && full && __builtin_popcount(bc.start_exit.mask) == 1) bc.start_stem = true;
            }
        }
        if (c.split && full) {  // fully crossed: done
            remove_from_list(bc, e, c.list);
            bc.crossing.erase(e);
            continue;
        }
        if (count != c.list) {
            remove_from_list(bc, e, c.list);
            c.list = count;
            bc.lists[count - 1].push_back(e);
        }
    }
}

/// Drops the partly crossed elements the search (`candidates`, sorted) no longer reaches: the blade
/// has left them (in 3D, one already cut that it ended inside is cut behind where it ended first:
/// end_stems_3d). The element the path began in keeps its crossing out (BladeCut::start_exit).
void drop_left(World& w, BladeCut& bc, const std::vector<int>& candidates, int tool) {
    std::vector<int> leaving;
    for (const auto& [e, c] : bc.crossing)
        if (!std::binary_search(candidates.begin(), candidates.end(), e)) leaving.push_back(e);
    std::sort(leaving.begin(), leaving.end());
    std::erase_if(bc.near, [&](const auto& n) { return !std::binary_search(candidates.begin(), candidates.end(), n.first); });
    w.cut_state.elements_split += end_stems_3d(w, bc, leaving, tool);
    for (int e : leaving) {
        const ElementCrossings& c = bc.crossing.at(e);
        if (e == bc.start_element && __builtin_popcount(c.mask) == 1 && !c.split) bc.start_exit = c;
        if (c.turn.element >= 0 && __builtin_popcount(c.mask) == 1 && queue_stem(w, e, c, material_position(w, c.turn), tool))
            ++w.cut_state.elements_split;
        remove_from_list(bc, e, c.list);
        bc.crossing.erase(e);
    }
}

}  // namespace

void close_at_start(World& w, int tool) {
    CutState& cs = w.cut_state;
    if (tool >= static_cast<int>(cs.blade.size())) return;
    BladeCut& bc = cs.blade[tool];
    const int e = bc.start_element;
    const auto it = e < 0 ? bc.crossing.end() : bc.crossing.find(e);
    const auto& cut = w.cuts.cut_of_element;  // empty in a world the enrichment never saw
    if (it == bc.crossing.end() || (!cut.empty() && cut[e] >= 0) || (!cs.queued.empty() && cs.queued[e])) return;
    ElementCrossings& c = it->second;
    const uint8_t out = bc.start_exit.mask;
    if (c.split || __builtin_popcount(c.mask) != 1 || __builtin_popcount(out) != 1 || c.mask == out) return;
    const int k = __builtin_ctz(out);
    c.mask |= out, c.t[k] = bc.start_exit.t[k], c.normal[k] = bc.start_exit.normal[k];
    bc.start_exit = ElementCrossings{};  // its crossing out is this split's: no stem from the start
    split_or_list(w, bc, {e}, tool, CutQuad{});
}

void stem_at_start(World& w, int tool) {
    CutState& cs = w.cut_state;
    if (tool >= static_cast<int>(cs.blade.size())) return;
    BladeCut& bc = cs.blade[tool];
    const int e = bc.start_element;
    if (!bc.start_stem || w.cuts.cut_of_element.empty() || w.cuts.cut_of_element[e] < 0) return;
    bc.start_stem = false;
    const int k = __builtin_ctz(bc.start_exit.mask);
    CutEvent ev;
    if (!stem_event(w, e, k, bc.start_exit.t[k], material_position(w, bc.start_point), ev)) return;
    ev.tool = tool;
    w.pending_cuts.push_back(ev);
    ++cs.elements_split;
}

void process_cut_quad(World& w, ElementBvh& bvh, const CutQuad& q, int tool, const CutQuad* face) {
    CutState& cs = w.cut_state;
    if (static_cast<int>(cs.blade.size()) <= tool) cs.blade.resize(tool + 1);
    BladeCut& bc = cs.blade[tool];
    const double t0 = wall_seconds();
    const int dim = w.elements.dim;
    ++cs.quads_built;
    cs.quads.push_back(q);
    std::vector<const CutQuad*> quads{&q};
    if (face) quads.push_back(face), cs.quads.push_back(*face);
    std::vector<std::array<Vec3, 2>> normals;
    for (const CutQuad* c : quads) normals.push_back(quad_normals(dim, *c));
    double length = 0.0;
    for (const CutQuad* c : quads)
        length = std::max({length, (c->corner[3] - c->corner[0]).norm(), (c->corner[2] - c->corner[1]).norm()});
    std::vector<int> candidates;
    if (!bc.front.empty() && !cs.bvh_every_quad) {
        const int depth = cs.min_depth + static_cast<int>(std::ceil(length / std::max(cs.mean_edge, 1e-300)));
        candidates = neighbourhood(w, bc.front, depth, quad_reach(quads, normals));
    } else {
        Vec3 centre = Vec3::Zero();
        for (const CutQuad* c : quads)
            for (const Vec3& v : c->corner) centre += v / (4.0 * quads.size());
        double radius = 0.0;
        for (const CutQuad* c : quads)
            for (const Vec3& v : c->corner) radius = std::max(radius, (v - centre).norm());
        bvh.ensure(mesh_view(w), cs.mean_edge);
        bvh.query_ball(centre, radius, candidates);
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    }
    note_stem_starts(w, bc, q, candidates);
    const auto& cut = w.cuts.cut_of_element;
    std::vector<int> crossed;
    thread_local NodeSides sides;
    sides.begin(w, quads);
    for (int e : candidates) {
        bool beside = false;
        if ((!cut.empty() && cut[e] >= 0) || (!cs.queued.empty() && cs.queued[e])) {
            const auto tip = bc.crossing.find(e);  // a progressive front's tip element is still tested
            // A cut element this blade entered is followed out of it, though the blade then turns
            // along the cut (a loop closing on its own wound); one it passes along its cut counts
            // the crossings away from the cut alone (beside).
            const bool recut = recut_allowed(w) && !cut.empty() && cut[e] >= 0;
            const bool entered = tip != bc.crossing.end() && !tip->second.split;
            const bool again = recut && (entered || cuts_across(w, e, normals[0][0]));
            beside = recut && !again;
            if (!again && !beside && (!cs.progressive || tip == bc.crossing.end() || !tip->second.split)) {
                for (size_t k = 0; k < quads.size(); ++k) note_recut(w, e, *quads[k], normals[k][0], tool);
                continue;
            }
        }
        ++cs.elements_tested;
        const int found = test_element(w, bc, e, quads, normals, beside, sides);
        if (beside && found == 0)
            for (size_t k = 0; k < quads.size(); ++k) note_recut(w, e, *quads[k], normals[k][0], tool);
        cs.crossings_found += found;
        if (found > 0) crossed.push_back(e);
    }
    const int queued_before = cs.elements_split;
    split_or_list(w, bc, crossed, tool, q);
    if (static_cast<int>(cs.split_by_tool.size()) <= tool) cs.split_by_tool.resize(tool + 1, 0);
    cs.split_by_tool[tool] += cs.elements_split - queued_before;
    note_stem_ends(w, bc, q);
    drop_left(w, bc, candidates, tool);
    const auto unreached = [&](const auto& b) { return !std::binary_search(candidates.begin(), candidates.end(), b.first); };
    std::erase_if(bc.began_in, unreached), std::erase_if(bc.ended_in, unreached);
    bc.front = crossed;
    const double ms = (wall_seconds() - t0) * 1e3;
    cs.update_ms += ms;
    cs.quad_ms.push_back(ms);
}

}  // namespace xcut
