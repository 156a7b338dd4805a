#include "systems/cut/enrichment_system.h"

#include "systems/kernels/mesh_measures.h"

#include <algorithm>
#include <fmt/format.h>

#include "engine/parallel.h"
#include "engine/setup.h"
#include "systems/cut/node_copies.h"
#include "systems/cut/quadratic_enrichment.h"
#include "systems/cut/recut.h"
#include "engine/fragment_geometry.h"
#include "engine/room_ahead.h"
#include "systems/kernels/cut_geometry.h"
#include "systems/xfem_queries.h"

namespace xcut {

namespace {

/// Calls f(array, room) for each array a split appends to, room being the entries reserved for it
/// (twice the mesh's elements or nodes): prepare_enrichment reserves them, fault_room_ahead makes
/// the next stretch of each resident.
template <class F>
void each_split_array(World& w, F f) {
    Elements& el = w.elements;
    const size_t e = static_cast<size_t>(w.mesh_elements) * 2;
    f(el.nodes, e), f(el.rest_volume, e), f(el.dm_inv, e), f(el.rotation, e), f(el.material, e), f(el.region, e);
    f(el.body, e), f(el.weight, e), f(w.forces.element_buffer, e);
    Nodes& n = w.nodes;
    const size_t m = static_cast<size_t>(w.mesh_nodes) * 2;
    f(n.rest, m), f(n.position, m), f(n.velocity, m), f(n.mass, m), f(n.fixed, m);
}

}  // namespace

void prepare_enrichment(World& w) {
    EnrichedDofs& en = w.enriched;
    if (static_cast<int>(en.sign.size()) == w.mesh_nodes) return;
    en.sign.assign(w.mesh_nodes, 0);
    en.enriched.assign(w.mesh_nodes, 0);
    en.front_fixed.assign(w.mesh_nodes, 0);
    en.phantom.assign(w.mesh_nodes, -1);
    en.sign_normal.assign(w.mesh_nodes, Vec3::Zero());
    w.cuts.cut_of_element.assign(w.mesh_elements, -1);
    // Room for virtual elements and phantom nodes, so a split never copies the whole mesh arrays
    // (a reallocation of 50k tets costs ~8 ms). Reserved pages are not touched until used, so this
    // costs address space, not resident memory (fault_room_ahead makes the next stretch resident).
    each_split_array(w, [](auto& v, size_t room) { v.reserve(room); });
    fault_room_ahead(w);
}

void fault_room_ahead(World& w) {
    CutElements& ce = w.cuts;
    const size_t elements = static_cast<size_t>(w.elements.count()), nodes = static_cast<size_t>(w.nodes.count());
    if (elements + kRoomAhead / 2 <= ce.room_elements && nodes + kRoomAhead / 2 <= ce.room_nodes) return;
    ce.room_elements = elements + kRoomAhead, ce.room_nodes = nodes + kRoomAhead;
    std::vector<RoomStretch> room;
    each_split_array(w, [&](const auto& v, size_t) { add_room_ahead(v, kRoomAhead, room); });
    populate_in_background(std::move(room));
}

namespace {

/// How event ev's level at local node a is turned against the side the node has: +1 alike, -1
/// opposite, 0 the node has no side yet.
int level_against_side(const World& w, const CutEvent& ev, int a) {
    const int s = w.enriched.sign[w.elements.nodes[ev.element][a]];
    return s == 0 ? 0 : (ev.level[a] >= 0.0) == (s > 0) ? 1 : -1;
}

/// Whether the sides the element's nodes already have cannot be the event's levels' in either
/// orientation: a loop that closes beside its first pass leaves on the outside a node that pass put
/// inside (the tissue moved under the blade). The cut's own line then decides, as for another
/// incision's.
bool sides_disagree(const World& w, const CutEvent& ev) {
    int orientation = 0;
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) {
        const int o = level_against_side(w, ev, a);
        if (o != 0 && orientation != 0 && o != orientation) return true;
        if (o != 0) orientation = o;
    }
    return false;
}

/// Where the sides of an element's nodes disagree with its own line (sides_disagree, not another
/// incision's): +1 or -1, how a node without a side turns the side its level gives, as the sides of
/// the node farthest from the line (that node's side is surest): a blade's levels follow its
/// normal, which a loop reverses. +1 for another incision's line (its sides are not these nodes').
int new_sides_orientation(const World& w, const CutEvent& ev, const CutLine& line) {
    if (signed_by_other_incision(w, ev.element, line.normal, incision_cos(w, ev))) return 1;
    const auto& c = w.elements.nodes[ev.element];
    int orient = 1;
    double farthest = -1.0;
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) {
        const double d = std::abs(line.normal.dot(w.nodes.rest[c[a]] - line.origin));
        const int o = level_against_side(w, ev, a);
        if (o != 0 && d > farthest) farthest = d, orient = o;
    }
    return orient;
}

/// Whether event ev is a cut of another incision than the one that gave one of its element's nodes
/// its side: its line is more than 30 degrees from the cut that fixed it (kRecutCos). Such an element
/// takes its sides and its points from the event, not from the nodes' sides and the edges' earlier
/// points, and its parts are those of its line (`line`; systems/cut/recut.h), where a world cuts
/// elements again.
bool other_incision(const World& w, const CutEvent& ev, CutLine& line) {
    return recut_allowed(w) && event_cut_line(w, ev, line) &&
           (signed_by_other_incision(w, ev.element, line.normal, incision_cos(w, ev)) || sides_disagree(w, ev));
}

/// Splits one element as `ev` asks; returns false if it is already cut or the signs do not differ.
bool record_cut(World& w, const CutEvent& ev) {
    const int e = ev.element;
    if (e < 0 || e >= w.mesh_elements || w.cuts.cut_of_element[e] >= 0) return false;
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element();
    const auto& c = el.nodes[e];
    EnrichedDofs& en = w.enriched;
    CutLine own_line;
    const bool own = other_incision(w, ev, own_line);
    // A node without a side takes its level's, turned as the nodes with one are against theirs:
    // a cut's polygon may face either way, and the sides an incision gave (a polyline's previous
    // segment, past their joint) are kept (sides_disagree: they agree in one orientation).
    int turn = 1;
    for (int a = 0; a < npe && !own; ++a)
        if (level_against_side(w, ev, a) != 0) turn = level_against_side(w, ev, a);
    std::array<int8_t, 4> H{};
    for (int a = 0; a < npe; ++a)
        H[a] = en.sign[c[a]] != 0 && !own ? en.sign[c[a]] : static_cast<int8_t>(turn * (ev.level[a] >= 0.0 ? 1 : -1));
    const int orient = own ? new_sides_orientation(w, ev, own_line) : 1;
    bool mixed = false;
    for (int a = 1; a < npe; ++a) mixed = mixed || H[a] != H[0];
    if (!mixed) return false;

    std::array<Vec3, 4> X;
    for (int a = 0; a < 4; ++a) X[a] = a < npe ? w.nodes.rest[c[a]] : Vec3::Zero();
    std::array<double, 6> t{};
    CutElements& ce = w.cuts;
    std::array<Vec3, 4> points;
    std::array<int8_t, 4> point_edge;
    points.fill(Vec3::Zero());
    point_edge.fill(-1);
    int np = 0;
    for (int k = 0; k < edge_count(dim); ++k) {
        const int i = edge_nodes(dim, k)[0], j = edge_nodes(dim, k)[1];
        if (H[i] == H[j]) continue;
        // The event's parameter; else where its levels change sign; else (a node's side fixed by an
        // earlier cut against this event's levels) the midpoint, never a point extrapolated onto a node.
        double tk = ev.edge_has_t[k] ? ev.edge_t[k] : 0.5;
        const double li = ev.level[i], lj = ev.level[j];
        if (!ev.edge_has_t[k] && li != lj && (li >= 0.0) != (lj >= 0.0)) tk = li / (li - lj);
        const double earlier = own ? -1.0 : crack_edge_param(w, c[i], c[j]);
        t[k] = earlier >= 0.0 ? earlier : std::clamp(tk, 0.0, 1.0);
        points[np] = edge_point(X, dim, k, t[k]);
        point_edge[np++] = static_cast<int8_t>(k);
    }
    // This cut's plane, its normal toward H = +1: kept by the nodes it gives a side.
    Vec3 normal = chord_normal(points.data(), np, dim);
    double toward = 0.0;
    for (int a = 0; a < npe; ++a) toward += H[a] * (X[a] - points[0]).dot(normal);
    if (toward < 0.0) normal = -normal;
    for (int a = 0; a < npe; ++a) {
        if (en.sign[c[a]] == 0) en.sign_normal[c[a]] = orient * normal, en.sign[c[a]] = static_cast<int8_t>(orient * H[a]);
        en.enriched[c[a]] = 1;
    }
    const double total = dim == 3 ? tet_side_volume(X, H, t, 1) + tet_side_volume(X, H, t, -1)
                                  : tri_side_area(X, H, t, 1) + tri_side_area(X, H, t, -1);
    const double above = dim == 3 ? tet_side_volume(X, H, t, 1) : tri_side_area(X, H, t, 1);
    ce.cut_of_element[e] = ce.count();
    ce.element.push_back(e);
    ce.fraction_above.push_back(std::clamp(above / total, 0.0, 1.0));
    ce.points.push_back(points);
    ce.point_edge.push_back(point_edge);
    ce.virtual_element.push_back({-1, -1});
    ce.crossed.push_back(ev.crossed);
    ce.entered_time.push_back(ev.entered_time >= 0.0 ? ev.entered_time : w.time);
    ce.entered_wall.push_back(ev.entered_wall >= 0.0 ? ev.entered_wall : wall_seconds());
    ce.opened.push_back(0);
    ce.tool.push_back(ev.tool);
    ce.lines.emplace_back();
    ce.line_edge_t.emplace_back();
    ce.fragments.emplace_back();
    if (own) {
        ce.lines.back().push_back(own_line);
        if (dim == 3) ce.line_edge_t.back().push_back(first_edge_params(w, ce.count() - 1));
    }
    sign_edge_nodes(w, e);
    return true;
}

/// An event for an element already cut (a progressive front's tip element): marks the edges the
/// blade has crossed since, and adds the nodes of those that are split to `affected`.
void record_crossings(World& w, const CutEvent& ev, std::vector<int>& affected) {
    if (ev.element < 0 || ev.element >= w.mesh_elements) return;
    const int c = w.cuts.cut_of_element[ev.element];
    if (c < 0) return;
    const uint8_t fresh = ev.crossed & ~w.cuts.crossed[c];
    if (fresh == 0) return;
    w.cuts.crossed[c] |= ev.crossed;
    const auto& nodes = w.elements.nodes[ev.element];
    for (int k = 0; k < edge_count(w.elements.dim); ++k) {
        if (!(fresh >> k & 1)) continue;
        const int i = nodes[edge_nodes(w.elements.dim, k)[0]], j = nodes[edge_nodes(w.elements.dim, k)[1]];
        if (w.enriched.sign[i] == w.enriched.sign[j]) continue;
        affected.push_back(i), affected.push_back(j);
        append_edge_nodes_around(w, i, affected), append_edge_nodes_around(w, j, affected);
        w.cuts.crossed_log.push_back({i, j});
    }
}

/// Records when cut element c first has a phantom vertex (the wound can open there): the time from
/// the blade's first crossing of it, simulated and wall.
void note_opening(World& w, int c) {
    CutElements& ce = w.cuts;
    if (ce.opened[c]) return;
    for (int v : fragments_of(w, c)) {
        const auto& verts = w.elements.nodes[w.virtual_elements.element[v]];
        for (int a = 0; a < w.elements.nodes_per_element(); ++a)
            if (verts[a] >= w.mesh_nodes) {
                ce.opened[c] = 1;
                ce.open_delay_sim.push_back(w.time - ce.entered_time[c]);
                ce.open_delay_wall.push_back(wall_seconds() - ce.entered_wall[c]);
                return;
            }
    }
}

/// Creates the two virtual elements of a newly cut element `c` over its own nodes (the copies the
/// nodes' material connectivity gives them are written next: assign_node_copies).
void create_virtual_elements(World& w, int c) {
    Elements& el = w.elements;
    const int e = w.cuts.element[c];
    const double fa = w.cuts.fraction_above[c];
    for (int s = 0; s < 2; ++s) {
        const int8_t side = s == 0 ? 1 : -1;
        w.cuts.virtual_element[c][s] = w.virtual_elements.count();
        w.virtual_elements.parent.push_back(e);
        w.virtual_elements.side.push_back(side);
        w.virtual_elements.mask.push_back((side > 0 ? 1u : 0u) | bound_by(0));
        w.virtual_elements.element.push_back(append_element_copy(el, e, std::max(side > 0 ? fa : 1.0 - fa, kMinSideFraction)));
    }
    el.weight[e] = 0.0;
    if (!w.cuts.lines[c].empty()) w.cuts.fragments[c] = {w.cuts.virtual_element[c][0], w.cuts.virtual_element[c][1]};
    add_quadratic_sides(w, c);
}

/// apply_cut_events for one batch: the events of elements an earlier event of the batch splits
/// are left in world.pending_cuts, to cut those elements again once they are split.
int apply_cut_batch(World& w) {
    prepare_enrichment(w);
    const int first_new = w.cuts.count();
    std::vector<int> affected;  // nodes whose hold is looked at again
    std::vector<int> update;    // cut elements whose virtual vertices change
    int recut = 0;
    std::vector<CutEvent> next;  // cuts through elements this batch splits
    for (CutEvent& ev : w.pending_cuts) {
        // A cut of this batch through an element an earlier one of it has just split (polygons
        // cut at one time that cross) cuts it again once it is split, as it would a step later.
        if (!ev.again && ev.element >= 0 && ev.element < w.mesh_elements && w.cuts.cut_of_element[ev.element] >= 0 &&
            recut_allowed(w)) {
            ev.again = true;
            next.push_back(ev);
            continue;
        }
        // A later crack meets the earlier ones on its edges (2D, where elements are cut again).
        if (recut_allowed(w)) join_earlier_points(w, ev);
        if (ev.again) {
            if (!record_recut(w, ev)) continue;
            ++recut;
            update.push_back(w.cuts.cut_of_element[ev.element]);
            w.cuts.recut_log.push_back(w.cuts.cut_of_element[ev.element]);
            for (int a = 0; a < w.elements.nodes_per_element(); ++a) affected.push_back(w.elements.nodes[ev.element][a]);
        } else if (!record_cut(w, ev)) {
            record_crossings(w, ev, affected);
        }
    }
    w.pending_cuts = std::move(next);
    const int split = w.cuts.count() - first_new + recut;
    if (split == 0 && affected.empty()) return 0;

    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    for (int c = first_new; c < w.cuts.count(); ++c)
        for (int a = 0; a < npe; ++a) {
            affected.push_back(el.nodes[w.cuts.element[c]][a]);
            // the mid-edge nodes around it (its own, and those the front's clause holds by its edges)
            append_edge_nodes_around(w, el.nodes[w.cuts.element[c]][a], affected);
        }
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());

    for (int c = first_new; c < w.cuts.count(); ++c) create_virtual_elements(w, c), update.push_back(c);
    assign_node_copies(w, affected, update);
    std::sort(update.begin(), update.end());
    update.erase(std::unique(update.begin(), update.end()), update.end());
    for (int c : update) note_opening(w, c);
    sync_quadratic_sides(w, update);

    build_virtual_incidence(w);
    std::vector<int> touched;  // every vertex of the updated virtual elements and of their parents
    for (int c : update) {
        for (int a = 0; a < npe; ++a) touched.push_back(el.nodes[w.cuts.element[c]][a]);
        for (int v : fragments_of(w, c)) {
            const auto& verts = el.nodes[w.virtual_elements.element[v]];
            touched.insert(touched.end(), verts.begin(), verts.begin() + npe);
        }
        append_quadratic_vertices(w, c, touched);
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    relump_nodes(w, touched);
    fault_room_ahead(w);
    return split;
}

}  // namespace

int apply_cut_events(World& w) {
    int split = 0;
    while (!w.pending_cuts.empty()) split += apply_cut_batch(w);  // then the cuts through elements it split
    return split;
}

SystemDesc enrichment_system() {
    return {"EnrichmentSystem", kNodes | kElements | kCutEvents, kNodes | kElements | kXfem | kCutEvents | kForces,
            [](World& w) {
                const int dofs_before = 3 * w.nodes.count();
                const int split = apply_cut_events(w);
                if (split > 0 && w.verbose)
                    fmt::print("t = {:.4g} s: {} elements split; DOFs {} -> {} ({} nodes + {} enriched)\n", w.time, split,
                               dofs_before, 3 * w.nodes.count(), w.mesh_nodes, w.enriched.count());
            }};
}

}  // namespace xcut
