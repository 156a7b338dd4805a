#include "systems/cut/quadratic_enrichment.h"

#include <algorithm>

#include "engine/quadratic_setup.h"
#include "systems/cut/enrichment_system.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/kernels/tet10_side_rule.h"

namespace xcut {
namespace {

/// The crossing parameter of every split edge of cut element c (kTetEdges order, 2D kTriEdges, from
/// the edge's first node): the crack's shared edge point (crack_edge_param), as its neighbours read it.
std::array<double, 6> edge_params(const World& w, int c) {
    const CutElements& ce = w.cuts;
    const auto& nodes = w.elements.nodes[ce.element[c]];
    std::array<double, 6> t{};
    for (int k = 0; k < 4 && ce.point_edge[c][k] >= 0; ++k) {
        const int edge = ce.point_edge[c][k];
        const int* ends = edge_nodes(w.elements.dim, edge);
        t[edge] = crack_edge_param(w, nodes[ends[0]], nodes[ends[1]]);
    }
    return t;
}

/// Side `side`'s rule and HRZ masses of a cut element whose corners have signs H and whose split
/// edges are crossed at t: a tetrahedron's, or a 6-node triangle's (`planar`: H's and t's first three).
void side_rule_and_masses(bool planar, const std::array<int8_t, 4>& H, const std::array<double, 6>& t, int side,
                          TetSideRule& rule, std::array<double, 10>& mass) {
    if (!planar) {
        rule = tet_side_rule(H, t, side);
        mass = tet10_side_masses(H, t, side);
        return;
    }
    const std::array<int8_t, 3> h{H[0], H[1], H[2]};
    const std::array<double, 3> s{t[0], t[1], t[2]};
    rule = tri_side_rule(h, s, side);
    mass = tri6_side_masses(h, s, side);
}

/// A side's rule and masses, floored at kMinSideFraction of the element: a side of no volume (a cut
/// through a face) takes the whole element's rule and masses at that fraction.
void floor_side(bool planar, const std::array<double, 6>& t, int side, TetSideRule& rule, std::array<double, 10>& mass) {
    double fraction = 0.0;
    for (int p = 0; p < rule.count; ++p) fraction += rule.weight[p];
    if (fraction >= kMinSideFraction) return;
    const double scale = fraction > 0.0 ? kMinSideFraction / fraction : kMinSideFraction;
    if (!(fraction > 0.0)) {
        const auto h = static_cast<int8_t>(side);
        side_rule_and_masses(planar, {h, h, h, h}, t, side, rule, mass);
    }
    for (int p = 0; p < rule.count; ++p) rule.weight[p] *= scale;
    for (double& m : mass) m *= scale;
}

}  // namespace

bool is_edge_node(const World& w, int i) {
    const QuadraticElements& q = w.quadratic;
    return q.count() > 0 && i >= q.first_edge_node && i < w.mesh_nodes;
}

void sign_edge_nodes(World& w, int e) {
    const int t0 = quadratic_entry(w, e);
    if (t0 < 0) return;
    EnrichedDofs& en = w.enriched;
    const auto& q = w.quadratic.nodes[t0];
    for (int k = 0; k < w.quadratic.edge_count(); ++k) {
        const int m = q[4 + k], i = q[kTet10Edges[k][0]], j = q[kTet10Edges[k][1]];
        if (en.sign[m] != 0) continue;
        int8_t side = en.sign[i];
        if (en.sign[i] != en.sign[j]) {
            double t = crack_edge_param(w, i, j);
            if (t < 0.0) t = 0.5;
            side = t < 0.5 ? en.sign[j] : t > 0.5 ? en.sign[i] : en.sign[std::min(i, j)];
        }
        en.sign[m] = side;
        en.sign_normal[m] = en.sign_normal[en.sign[i] == side ? i : j];
        en.enriched[m] = 1;
    }
}

void add_quadratic_sides(World& w, int c) {
    const int e = w.cuts.element[c], t0 = quadratic_entry(w, e);
    if (t0 < 0) return;
    QuadraticElements& q = w.quadratic;
    std::array<int8_t, 4> H{};
    for (int a = 0; a < w.elements.nodes_per_element(); ++a) H[a] = w.enriched.sign[w.elements.nodes[e][a]];
    const std::array<double, 6> t = edge_params(w, c);
    q.of_element.resize(w.elements.count(), -1);
    q.side_rule.resize(q.count(), -1);
    for (int s = 0; s < 2; ++s) {
        const int side = s == 0 ? 1 : -1;
        const int ve = w.virtual_elements.element[w.cuts.virtual_element[c][s]];
        TetSideRule rule;
        std::array<double, 10> mass;
        side_rule_and_masses(q.planar, H, t, side, rule, mass);
        floor_side(q.planar, t, side, rule, mass);
        q.of_element[ve] = q.count();
        q.element.push_back(ve);
        q.nodes.push_back(q.nodes[t0]);
        q.side_rule.push_back(static_cast<int>(q.side_rules.size()));
        q.side_rules.push_back(rule);
        q.side_masses.push_back(mass);
    }
}

void append_edge_nodes_around(const World& w, int i, std::vector<int>& out) {
    const QuadraticElements& q = w.quadratic;
    if (q.count() == 0 || i + 1 >= static_cast<int>(q.incidence.offset.size())) return;
    for (int p = q.incidence.offset[i]; p < q.incidence.offset[i + 1]; ++p) {
        const int t = q.incidence.entry[p] >> 4;
        if (q.element[t] < w.mesh_elements) out.insert(out.end(), q.nodes[t].begin() + 4, q.nodes[t].end());
    }
}

void sync_quadratic_sides(World& w, const std::vector<int>& cuts) {
    QuadraticElements& q = w.quadratic;
    if (q.count() == 0) return;
    bool any = false;
    for (int c : cuts)
        for (int s = 0; s < 2; ++s) {
            const int ve = w.virtual_elements.element[w.cuts.virtual_element[c][s]];
            const int t = ve < static_cast<int>(q.of_element.size()) ? q.of_element[ve] : -1;
            if (t < 0) continue;
            std::copy(w.elements.nodes[ve].begin(), w.elements.nodes[ve].begin() + w.elements.nodes_per_element(),
                      q.nodes[t].begin());
            fill_absent_slots(q, q.nodes[t]);
            any = true;
        }
    if (any || static_cast<int>(q.incidence.offset.size()) != w.nodes.count() + 1) build_quadratic_incidence(w);
}

void append_quadratic_vertices(const World& w, int c, std::vector<int>& out) {
    const QuadraticElements& q = w.quadratic;
    const int t0 = quadratic_entry(w, w.cuts.element[c]);
    if (t0 < 0) return;
    out.insert(out.end(), q.nodes[t0].begin(), q.nodes[t0].end());
    for (int s = 0; s < 2; ++s) {
        const int t = q.of_element[w.virtual_elements.element[w.cuts.virtual_element[c][s]]];
        out.insert(out.end(), q.nodes[t].begin(), q.nodes[t].end());
    }
}

}  // namespace xcut
