#include "systems/cut/enrichment_system.h"

#include "systems/kernels/mesh_measures.h"

#include <algorithm>
#include <fmt/format.h>

#include "engine/parallel.h"
#include "engine/setup.h"
#include "systems/kernels/cut_geometry.h"
#include "systems/xfem_queries.h"

namespace xcut {

void prepare_enrichment(World& w) {
    EnrichedDofs& en = w.enriched;
    if (static_cast<int>(en.sign.size()) == w.mesh_nodes) return;
    en.sign.assign(w.mesh_nodes, 0);
    en.enriched.assign(w.mesh_nodes, 0);
    en.front_fixed.assign(w.mesh_nodes, 0);
    en.phantom.assign(w.mesh_nodes, -1);
    en.sign_point.assign(w.mesh_nodes, Vec3::Zero());
    en.sign_normal.assign(w.mesh_nodes, Vec3::Zero());
    w.cuts.cut_of_element.assign(w.mesh_elements, -1);
    // Room for virtual elements and phantom nodes, so a split never copies the whole mesh arrays
    // (a reallocation of 50k tets costs ~8 ms). Reserved pages are not touched until used, so this
    // costs address space, not resident memory.
    Elements& el = w.elements;
    const size_t e_cap = static_cast<size_t>(w.mesh_elements) * 2;
    el.nodes.reserve(e_cap), el.rest_volume.reserve(e_cap), el.dm_inv.reserve(e_cap);
    el.rotation.reserve(e_cap), el.material.reserve(e_cap), el.region.reserve(e_cap), el.body.reserve(e_cap), el.weight.reserve(e_cap);
    w.forces.element_buffer.reserve(e_cap);
    Nodes& n = w.nodes;
    const size_t n_cap = static_cast<size_t>(w.mesh_nodes) * 2;
    n.rest.reserve(n_cap), n.position.reserve(n_cap), n.velocity.reserve(n_cap);
    n.mass.reserve(n_cap), n.fixed.reserve(n_cap);
}

namespace {

/// How clearly on the node's own side of its first cut element c's other part must lie to be another
/// incision: 0.1 of c's shortest edge [-]. A first cut through or near the node's layer puts the
/// parts of the elements that continue it on that plane; they continue the incision.
constexpr double kOtherIncisionMargin = 0.1;

/// Whether cut element c uses node j's phantom for its part on the other side from j. The phantom
/// is the copy of j across the cut that fixed H_j (its plane: EnrichedDofs::sign_point,
/// sign_normal), so it carries the material across that plane. Element c's other part lies there
/// when c continues that incision, straight or turning; it does not when c belongs to another
/// incision that reaches j from j's own side of the first (a T, an X, a loop closing on itself):
/// then c keeps the real node on both sides at j, as the crack-front rule does, and that incision
/// does not open at j. Sharing the phantom would tie c's other part to the first wound's far lip
/// (the elastic energy of a multi-blade trajectory jumped 25-fold at such a split,
/// docs/BENCHMARKS.md).
bool same_incision(const World& w, int c, int j) {
    const EnrichedDofs& en = w.enriched;
    const Vec3& normal = en.sign_normal[j];
    if (normal.squaredNorm() == 0.0) return true;
    const Elements& el = w.elements;
    const auto& nodes = el.nodes[w.cuts.element[c]];
    Vec3 centre = Vec3::Zero();
    int n = 0;
    for (int a = 0; a < el.nodes_per_element(); ++a)
        if (en.sign[nodes[a]] != en.sign[j]) centre += w.nodes.rest[nodes[a]], ++n;
    if (n == 0) return true;
    const double across = (centre / n - en.sign_point[j]).dot(normal) * en.sign[j];
    return across <= kOtherIncisionMargin * shortest_edge(el, w.nodes.rest.data(), w.cuts.element[c]);
}

/// Splits one element as `ev` asks; returns false if it is already cut or the signs do not differ.
bool record_cut(World& w, const CutEvent& ev) {
    const int e = ev.element;
    if (e < 0 || e >= w.mesh_elements || w.cuts.cut_of_element[e] >= 0) return false;
    const Elements& el = w.elements;
    const int dim = el.dim, npe = el.nodes_per_element();
    const auto& c = el.nodes[e];
    EnrichedDofs& en = w.enriched;
    std::array<int8_t, 4> H{};
    for (int a = 0; a < npe; ++a) H[a] = en.sign[c[a]] != 0 ? en.sign[c[a]] : (ev.level[a] >= 0.0 ? 1 : -1);
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
        const double earlier = crack_edge_param(w, c[i], c[j]);
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
        if (en.sign[c[a]] == 0) en.sign_point[c[a]] = points[0], en.sign_normal[c[a]] = normal;
        en.sign[c[a]] = H[a];
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
        w.cuts.crossed_log.push_back({i, j});
    }
}

/// Crack-front rule (§3.5): node j keeps a_j = 0 while a crossed edge (j, k) of a cut element is
/// also an edge of an uncut element, i.e. while the crack front runs through that neighbour; and,
/// on a progressive front, while such an edge lies on the cut's extension ahead of the blade (no
/// cut element has it crossed: edge_crossed).
bool held_by_front(const World& w, int j) {
    const Incidence& inc = w.incidence;
    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    for (int p = inc.offset[j]; p < inc.offset[j + 1]; ++p) {
        const int e = inc.entry[p] >> 2;
        if (w.cuts.cut_of_element[e] < 0) continue;
        for (int b = 0; b < npe; ++b) {
            const int k = el.nodes[e][b];
            if (k == j || w.enriched.sign[k] == w.enriched.sign[j]) continue;
            if (!edge_crossed(w, j, k)) return true;
            // Crossed edge (j, k): is there an uncut element containing it?
            for (int q = inc.offset[j]; q < inc.offset[j + 1]; ++q) {
                const int f = inc.entry[q] >> 2;
                if (w.cuts.cut_of_element[f] >= 0) continue;
                const auto& fn = el.nodes[f];
                if (std::find(fn.begin(), fn.begin() + npe, k) != fn.begin() + npe) return true;
            }
        }
    }
    return false;
}

void add_phantom(World& w, int j) {
    Nodes& n = w.nodes;
    const int p = n.count();
    n.rest.push_back(n.rest[j]);
    n.position.push_back(n.position[j]);
    n.velocity.push_back(n.velocity[j]);
    n.mass.push_back(0.0);
    n.fixed.push_back(n.fixed[j]);
    w.enriched.phantom[j] = p;
    w.enriched.node_of_phantom.push_back(j);
    Eigen::VectorXd& dv = w.forces.last_dv;
    if (dv.size() == 3 * p) {
        dv.conservativeResize(3 * p + 3);
        dv.segment<3>(3 * p) = dv.segment<3>(3 * j);
    }
}

/// Records when cut element c first has a phantom vertex (the wound can open there): the time from
/// the blade's first crossing of it, simulated and wall.
void note_opening(World& w, int c) {
    CutElements& ce = w.cuts;
    if (ce.opened[c]) return;
    const auto& verts = w.elements.nodes[w.virtual_elements.element[ce.virtual_element[c][0]]];
    const auto& other = w.elements.nodes[w.virtual_elements.element[ce.virtual_element[c][1]]];
    for (int a = 0; a < w.elements.nodes_per_element(); ++a)
        if (verts[a] >= w.mesh_nodes || other[a] >= w.mesh_nodes) {
            ce.opened[c] = 1;
            ce.open_delay_sim.push_back(w.time - ce.entered_time[c]);
            ce.open_delay_wall.push_back(wall_seconds() - ce.entered_wall[c]);
            return;
        }
}

/// Creates or updates the two virtual elements of cut element `c` (vertex = real node on its own
/// side, phantom on the other side, or the real node while the front rule holds a_j = 0).
void build_virtual_elements(World& w, int c) {
    Elements& el = w.elements;
    const int e = w.cuts.element[c], npe = el.nodes_per_element();
    const double fa = w.cuts.fraction_above[c];
    for (int s = 0; s < 2; ++s) {
        const int8_t side = s == 0 ? 1 : -1;
        std::array<int, 4> verts = el.nodes[e];
        for (int a = 0; a < npe; ++a) {
            const int j = el.nodes[e][a];
            if (w.enriched.sign[j] != side && w.enriched.phantom[j] >= 0 && same_incision(w, c, j))
                verts[a] = w.enriched.phantom[j];
        }
        int& ve = w.cuts.virtual_element[c][s];
        if (ve >= 0) {
            el.nodes[w.virtual_elements.element[ve]] = verts;
            continue;
        }
        ve = w.virtual_elements.count();
        w.virtual_elements.parent.push_back(e);
        w.virtual_elements.side.push_back(side);
        const int added = append_element_copy(el, e, std::max(side > 0 ? fa : 1.0 - fa, kMinSideFraction));
        el.nodes[added] = verts;
        w.virtual_elements.element.push_back(added);
    }
    el.weight[e] = 0.0;
    note_opening(w, c);
}

}  // namespace

int apply_cut_events(World& w) {
    if (w.pending_cuts.empty()) return 0;
    prepare_enrichment(w);
    const int first_new = w.cuts.count();
    std::vector<int> affected;  // nodes whose hold is looked at again
    for (const CutEvent& ev : w.pending_cuts)
        if (!record_cut(w, ev)) record_crossings(w, ev, affected);
    w.pending_cuts.clear();
    const int split = w.cuts.count() - first_new;
    if (split == 0 && affected.empty()) return 0;

    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    for (int c = first_new; c < w.cuts.count(); ++c)
        for (int a = 0; a < npe; ++a) affected.push_back(el.nodes[w.cuts.element[c]][a]);
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());

    std::vector<int> update;  // cut elements whose virtual vertices change
    for (int c = first_new; c < w.cuts.count(); ++c) update.push_back(c);
    for (int j : affected) {
        w.enriched.front_fixed[j] = held_by_front(w, j) ? 1 : 0;
        if (w.enriched.front_fixed[j] || w.enriched.phantom[j] >= 0) continue;
        add_phantom(w, j);
        const Incidence& inc = w.incidence;
        for (int p = inc.offset[j]; p < inc.offset[j + 1]; ++p) {
            const int c = w.cuts.cut_of_element[inc.entry[p] >> 2];
            if (c >= 0 && c < first_new) update.push_back(c);
        }
    }
    std::sort(update.begin(), update.end());
    update.erase(std::unique(update.begin(), update.end()), update.end());
    for (int c : update) build_virtual_elements(w, c);

    build_virtual_incidence(w);
    std::vector<int> touched;  // every vertex of the updated virtual elements and of their parents
    for (int c : update) {
        for (int a = 0; a < npe; ++a) touched.push_back(el.nodes[w.cuts.element[c]][a]);
        for (int s = 0; s < 2; ++s) {
            const auto& verts = el.nodes[w.virtual_elements.element[w.cuts.virtual_element[c][s]]];
            touched.insert(touched.end(), verts.begin(), verts.begin() + npe);
        }
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    relump_nodes(w, touched);
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
