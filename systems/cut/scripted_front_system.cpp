#include "systems/cut/scripted_front_system.h"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>

#include "systems/cut/crack_tip_system.h"
#include "systems/kernels/front_enrichment.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

/// How far past an edge's end its line may run inside an element and still be that edge's front:
/// rounding, against the element's size [-].
constexpr double kEndTolerance = 1e-9;

std::array<Vec3, 4> rest_tet(const World& w, int e) {
    const auto& n = w.elements.nodes[e];
    return {w.nodes.rest[n[0]], w.nodes.rest[n[1]], w.nodes.rest[n[2]], w.nodes.rest[n[3]]};
}

/// Whether rest point X lies in (or on) a live triangle of the 2D mesh.
bool in_tissue_2d(const World& w, const Vec3& X) {
    for (int e = 0; e < w.mesh_elements; ++e) {
        if (w.elements.weight[e] <= 0.0) continue;
        const auto& n = w.elements.nodes[e];
        const Vec3 &A = w.nodes.rest[n[0]], &B = w.nodes.rest[n[1]], &C = w.nodes.rest[n[2]];
        Eigen::Matrix2d D;
        D << (B - A).head<2>(), (C - A).head<2>();
        const Eigen::Vector2d l = D.partialPivLu().solve((X - A).head<2>());
        if (std::min({1.0 - l.x() - l.y(), l.x(), l.y()}) >= -1e-12) return true;
    }
    return false;
}

std::vector<CutFront> segment_tips(const World& w, const std::vector<Vec3>& segment) {
    std::vector<CutFront> tips;
    for (int k = 0; k < 2; ++k) {
        const Vec3 &end = segment[k], &other = segment[1 - k];
        if (in_tissue_2d(w, end)) tips.push_back({end, (end - other).normalized(), Vec3::UnitZ()});
    }
    if (tips.empty())
        throw std::invalid_argument("both ends of the segment lie outside the tissue: the cut leaves no tip to enrich");
    return tips;
}

/// Whether polygon edge P -> Q runs through the tissue; throws when its line also runs through an
/// element beyond either end (the front would end inside the tissue).
bool edge_in_tissue(const World& w, const Vec3& P, const Vec3& Q, int edge) {
    const double length = (Q - P).norm();
    if (!(length > 0.0)) return false;
    const Vec3 t = (Q - P) / length;
    const Vec3 any = std::abs(t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const FrontFrame line{P, t.cross(any).normalized(), t};
    bool through = false;
    for (int e = 0; e < w.mesh_elements; ++e) {
        double from = 0.0, to = 0.0;
        if (w.elements.weight[e] <= 0.0) continue;
        const std::array<Vec3, 4> X = rest_tet(w, e);
        if (!front_in_tet(X, line, from, to)) continue;
        const double pad = kEndTolerance * (X[1] - X[0]).norm() + kEndTolerance * length;
        if (to <= pad || from >= length - pad) continue;  // the line beyond the edge, not the edge
        through = true;
        if (from < -pad || to > length + pad)
            throw std::invalid_argument(fmt::format(
                "the polygon's edge {} ends inside the tissue (element {}): only a straight front that crosses the "
                "tissue whole is enriched, not one with an end or a corner inside it", edge, e));
    }
    return through;
}

std::vector<CutFront> polygon_front(const World& w, const std::vector<Vec3>& polygon) {
    Vec3 normal = Vec3::Zero();  // Newell's: the polygon runs counter-clockwise about it
    const size_t n = polygon.size();
    for (size_t i = 0; i < n; ++i) normal += polygon[i].cross(polygon[(i + 1) % n]);
    std::vector<int> edges;
    for (size_t i = 0; i < n; ++i)
        if (edge_in_tissue(w, polygon[i], polygon[(i + 1) % n], static_cast<int>(i))) edges.push_back(static_cast<int>(i));
    if (edges.empty())
        throw std::invalid_argument("no edge of the polygon runs through the tissue: the cut leaves no front to enrich");
    if (edges.size() > 1)
        throw std::invalid_argument(fmt::format("the polygon's edges {} and {} both run through the tissue: a front "
                                                "with corners is not enriched (one straight front a cut)", edges[0], edges[1]));
    const Vec3 &P = polygon[edges[0]], &Q = polygon[(edges[0] + 1) % n];
    const Vec3 t = (Q - P).normalized();
    return {{P, t.cross(normal).normalized(), t}};  // outward: the interior lies to the left of the edge
}

/// Whether a cut element from `first` on (CutElements index) shares a node with an element of a
/// front's zone: its parts, or its nodes' sides, may have changed (a split elsewhere changes
/// neither).
bool cuts_reach_zones(const World& w, int first) {
    const CrackTips& ct = w.tips;
    const int corners = w.elements.nodes_per_element();
    std::vector<uint8_t> near(w.mesh_nodes, 0);
    for (int z = 0; z < ct.zone(); ++z)
        for (int k = 0; k < corners; ++k) near[mesh_node(w, w.elements.nodes[ct.element[z]][k])] = 1;
    for (int c = std::max(first, 0); c < w.cuts.count(); ++c)
        for (int k = 0; k < corners; ++k)
            if (near[mesh_node(w, w.elements.nodes[w.cuts.element[c]][k])]) return true;
    return false;
}

}  // namespace

std::vector<CutFront> scripted_cut_fronts(const World& w, const std::vector<Vec3>& polygon) {
    if (w.elements.dim == 2) {
        if (polygon.size() != 2) throw std::invalid_argument("a 2D cut is a segment: 2 points");
        return segment_tips(w, polygon);
    }
    if (polygon.size() < 3) throw std::invalid_argument("a 3D cut is a polygon: at least 3 points");
    return polygon_front(w, polygon);
}

bool has_scripted_fronts(const World& w) {
    return std::any_of(w.cut_plan.cuts.begin(), w.cut_plan.cuts.end(), [](const ScriptedCut& c) { return c.front_radius >= 0.0; });
}

bool enrich_scripted_fronts(World& w) {
    std::vector<ScriptedCut>& cuts = w.cut_plan.cuts;
    const bool fresh = std::any_of(cuts.begin(), cuts.end(),
                                   [](const ScriptedCut& c) { return c.front_radius >= 0.0 && c.applied && !c.front_enriched; });
    const bool any = std::any_of(cuts.begin(), cuts.end(), [](const ScriptedCut& c) { return c.front_enriched; });
    if (!fresh && (!any || w.cuts.count() == w.tips.cuts_seen)) return false;
    if (!fresh && !cuts_reach_zones(w, w.tips.cuts_seen)) {  // split elsewhere: the zones stand as they are
        w.tips.cuts_seen = w.cuts.count();
        return false;
    }
    clear_tip_zones(w.tips);  // every front again: their zones' parts follow the cut elements
    for (size_t i = 0; i < cuts.size(); ++i) {
        ScriptedCut& c = cuts[i];
        if (c.front_radius < 0.0 || !c.applied) continue;
        try {
            for (const CutFront& f : scripted_cut_fronts(w, c.polygon)) {
                if (w.elements.dim == 3) enrich_crack_front(w, f.point, f.direction, f.tangent, TipZone{c.front_radius});
                else enrich_crack_tip(w, f.point, f.direction, TipZone{c.front_radius});
            }
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(fmt::format("cuts[{}].front: {}", i, e.what()));
        }
        c.front_enriched = true;
    }
    w.tips.cuts_seen = w.cuts.count();
    return true;
}

SystemDesc scripted_front_system() {
    SystemDesc s{"ScriptedFrontSystem", kNodes | kElements | kCutPlan, kXfem, [](World& w) { enrich_scripted_fronts(w); },
                 "the scripted cuts' crack fronts, enriched"};
    return s.also_reads(kXfem);
}

}  // namespace xcut
