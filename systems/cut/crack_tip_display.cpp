// What is shown inside a 2D crack tip's element (systems/cut/crack_tip_system.h, show_crack_tips),
// and the CrackTipDisplaySystem that takes the step's amplitudes for the surface and the volume output.
#include <algorithm>

#include "systems/cut/crack_tip_system.h"
#include "systems/xfem_queries.h"

namespace xcut {

using namespace tip_triangles;

namespace {

/// Where the crack behind tip f enters triangle X (systems/kernels/branch_enrichment.h, ray_exit).
bool crack_entry(const std::array<Vec2, 3>& X, const TipFrame& f, int& edge, Vec2& E) {
    return ray_exit(X, f.point, -f.direction, -1, edge, E);
}

/// The uncut mesh element of the zone that holds tip f strictly inside; -1 if none.
int tip_element(const World& w, const TipFrame& f) {
    const CrackTips& ct = w.tips;
    const std::vector<int>& cut_of = w.cuts.cut_of_element;
    for (int z = 0; z < ct.zone(); ++z) {
        const int e = ct.element[z];
        if (e >= w.mesh_elements || (e < static_cast<int>(cut_of.size()) && cut_of[e] >= 0)) continue;
        if (w.elements.weight[e] > 0.0 && barycentric(rest_triangle(w, e), f.point).minCoeff() > 1e-9) return e;
    }
    return -1;
}

}  // namespace

void show_crack_tips(World& w) {
    CrackTips& ct = w.tips;
    ct.shown_step = w.step;
    ct.shown_tip.clear(), ct.shown_element.clear(), ct.shown_cells.clear();
    ct.shown_rest.clear(), ct.shown_position.clear(), ct.shown_velocity.clear();
    if (ct.count() == 0 || w.elements.dim != 2) return;
    const Eigen::VectorXd& b = step_tip_amplitudes(w);
    for (int tip = 0; tip < ct.count(); ++tip) {
        const TipFrame f{xy(ct.point[tip]), xy(ct.direction[tip])};
        const int e = tip_element(w, f);
        int edge = -1;
        Vec2 E = Vec2::Zero();
        if (e < 0 || std::count(ct.shown_element.begin(), ct.shown_element.end(), e) > 0) continue;
        const std::array<Vec2, 3> corners = rest_triangle(w, e);
        if (!crack_entry(corners, f, edge, E)) continue;
        const auto& n = w.elements.nodes[e];
        const int a = kTriEdges[edge][0], c = kTriEdges[edge][1], o = 3 - a - c;
        const int lip_a = cross2(f.direction, xy(w.nodes.rest[n[a]]) - f.point) > 0.0 ? 1 : -1;
        const double z = w.nodes.rest[n[a]].z();
        const std::array<Vec2, 3> X{E, E, f.point};
        const std::array<int, 3> lip{lip_a, -lip_a, 0};
        std::array<Vec3, 3> rest, position, velocity;
        for (int p = 0; p < 3; ++p) {
            rest[p] = Vec3(X[p].x(), X[p].y(), z);
            const Vec3 L = barycentric(corners, X[p]);
            position[p] = tip_field(w, b, e, X[p], L, tip, lip[p]);
            velocity[p] = L[0] * w.nodes.velocity[n[0]] + L[1] * w.nodes.velocity[n[1]] + L[2] * w.nodes.velocity[n[2]];
        }
        // Fanned from the tip (point 2): a and the entry on a's lip (point 0), the entry on c's lip
        // (point 1) and c, then the two whole edges.
        ct.shown_tip.push_back(tip), ct.shown_element.push_back(e);
        ct.shown_cells.push_back({-3, n[a], -1, -3, -2, n[c], -3, n[c], n[o], -3, n[o], n[a]});
        ct.shown_rest.push_back(rest), ct.shown_position.push_back(position), ct.shown_velocity.push_back(velocity);
    }
}

SystemDesc crack_tip_display_system() {
    SystemDesc s{"CrackTipDisplaySystem", kNodes | kElements, kXfem,
                 [](World& w) {
                     const OutputSettings& o = w.output;
                     const bool volume = o.vtu && output_frame_due(o, w.step);
                     if (w.tips.count() == 0 || !(volume || w.visual.vertex_count() > 0)) return;
                     step_tip_amplitudes(w);  // the step's own: no factor
                     show_crack_tips(w);
                 },
                 "the crack tips' amplitudes for the visual surface; the opening inside the tips' elements for the "
                 "volume output (2D)"};
    return s.also_reads(kXfem | kOutput | kSurfaces);
}

}  // namespace xcut
