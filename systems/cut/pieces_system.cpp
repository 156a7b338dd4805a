#include "systems/cut/pieces_system.h"

#include <fmt/format.h>

#include <numeric>
#include <utility>

#include "systems/cut/enrichment_system.h"
#include "systems/kernels/disjoint_sets.h"
#include "systems/xfem_queries.h"

namespace xcut {

namespace {

/// A force element that joins what it touches: not a cut mesh element (weight 0), nor a side whose
/// weight is the floor kMinSideFraction (a cut through its face or node: no material, 1e-9 of the
/// stiffness).
bool carries_volume(double weight) { return weight > kMinSideFraction; }

std::array<long long, 6> topology_of(const World& w) {
    return {w.cuts.count(), w.enriched.count(), w.snap.elements_split, w.snap.copies, w.elements.count(),
            w.nodes.count()};
}

/// Mean rest volume of each body's mesh elements [m^3].
std::vector<double> mean_element_volume(const World& w) {
    std::vector<double> sum(w.body_names.size(), 0.0), n(w.body_names.size(), 0.0);
    for (int e = 0; e < w.mesh_elements; ++e) {
        const size_t b = static_cast<size_t>(w.elements.body[e]);
        if (b >= sum.size()) sum.resize(b + 1, 0.0), n.resize(b + 1, 0.0);
        sum[b] += w.elements.rest_volume[e], n[b] += 1.0;
    }
    for (size_t b = 0; b < sum.size(); ++b) sum[b] = n[b] > 0.0 ? sum[b] / n[b] : 0.0;
    return sum;
}

/// The piece force element `e` was in at the last count: its own, or, for a virtual element or a
/// snapping piece made since, its mesh element's (-1: none).
int counted_before(const World& w, const std::vector<int>& old_of_element, int e) {
    const auto old = [&](int i) { return i < static_cast<int>(old_of_element.size()) ? old_of_element[i] : -1; };
    if (old(e) >= 0 || e < w.mesh_elements) return old(e);
    const int parent = mesh_element_of(w, e);
    return parent < 0 ? -1 : old(parent);
}

}  // namespace

bool count_pieces(World& w) {
    Pieces& p = w.pieces;
    const std::array<long long, 6> topology = topology_of(w);
    if (topology == p.topology) return false;
    p.topology = topology;

    const Elements& el = w.elements;
    const int npe = el.nodes_per_element();
    DisjointSets sets(w.nodes.count());
    for (int e = 0; e < el.count(); ++e) {
        if (!carries_volume(el.weight[e])) continue;
        for (int a = 1; a < npe; ++a) sets.join(el.nodes[e][0], el.nodes[e][a]);
    }
    // Pieces numbered in the order of their first force element.
    std::vector<int> piece_of_root(w.nodes.count(), -1);
    std::vector<int> old_of_element = std::move(p.of_element);
    p.of_element.assign(el.count(), -1);
    p.volume.clear(), p.anchored.clear(), p.body.clear(), p.sliver.clear();
    for (int e = 0; e < el.count(); ++e) {
        if (!carries_volume(el.weight[e])) continue;
        int& id = piece_of_root[sets.find(el.nodes[e][0])];
        if (id < 0) {
            id = static_cast<int>(p.volume.size());
            p.volume.push_back(0.0), p.anchored.push_back(0), p.body.push_back(el.body[e]);
        }
        p.of_element[e] = id;
        p.volume[id] += el.rest_volume[e] * el.weight[e];
    }
    // Anchored: a node held on an axis of the body's space (2D: x or y; every 2D node is held in z).
    const uint8_t axes = el.dim == 3 ? 7 : 3;
    for (int i = 0; i < w.nodes.count(); ++i) {
        const int id = (w.nodes.fixed[i] & axes) != 0 ? piece_of_root[sets.find(i)] : -1;
        if (id >= 0) p.anchored[id] = 1;
    }
    const std::vector<double> mean = mean_element_volume(w);
    p.count = 0;
    for (size_t k = 0; k < p.volume.size(); ++k) {
        const size_t b = static_cast<size_t>(p.body[k]);
        p.sliver.push_back(b < mean.size() && p.volume[k] < kSliverPiece * mean[b]);
        p.count += !p.sliver.back();
    }
    if (p.initial < 0) {
        p.initial = p.count;
        return true;
    }
    // A piece made by a cut: of the pieces an earlier piece became, all but its heir, which keeps
    // being that piece: the largest anchored one, else the largest (a cut frees what it parts from
    // what holds it). Each new piece is traced through its elements counted before.
    std::vector<int> heir_of_old, old_piece(p.volume.size(), -1);
    for (int e = 0; e < el.count(); ++e) {
        const int now = p.of_element[e];
        if (now < 0 || old_piece[now] >= 0) continue;
        const int before = counted_before(w, old_of_element, e);
        if (before >= 0) old_piece[now] = before;
    }
    for (size_t k = 0; k < p.volume.size(); ++k) {
        const int q = old_piece[k];
        if (q < 0) continue;
        if (q >= static_cast<int>(heir_of_old.size())) heir_of_old.resize(q + 1, -1);
        int& h = heir_of_old[q];
        if (h < 0 || std::make_pair(p.anchored[k], p.volume[k]) > std::make_pair(p.anchored[h], p.volume[h]))
            h = static_cast<int>(k);
    }
    for (size_t k = 0; k < p.volume.size(); ++k) {
        if (p.sliver[k]) continue;
        const int q = old_piece[k];
        if (q >= 0 && heir_of_old[q] == static_cast<int>(k)) continue;
        p.log.push_back({w.step, w.time, p.volume[k], p.body[k], p.anchored[k] != 0});
        if (w.verbose)
            fmt::print("t = {:.4g} s: a cut freed a piece of {} ({:.4g} cm^3, {}); {} pieces now\n", w.time,
                       w.body_names[p.body[k]], p.volume[k] * 1e6, p.anchored[k] ? "held by a constraint" : "free",
                       p.count);
    }
    return true;
}

std::string pieces_report(const World& w) {
    const Pieces& p = w.pieces;
    if (p.log.empty()) return "";
    std::string made;
    for (const PieceEvent& e : p.log)
        made += fmt::format("{}{:.4g} cm^3 of {} at t = {:.4g} s ({})", made.empty() ? "" : "; ", e.volume * 1e6,
                            w.body_names[e.body], e.time, e.anchored ? "held" : "free");
    return fmt::format("pieces: {} ({} at the start); cuts freed {}: {}", p.count, p.initial, p.log.size(), made);
}

SystemDesc pieces_system() {
    return {"PiecesSystem", kNodes | kElements | kCutEvents, kPieces, [](World& w) { count_pieces(w); }};
}

}  // namespace xcut
