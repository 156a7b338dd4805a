#include "systems/cut/material_anchor.h"

#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"  // triangle_barycentric
#include "systems/cut/cut_system.h"    // mesh_view

namespace xcut {

namespace {

/// Tolerance [-] on a barycentric coordinate for a point on an element's face or edge.
constexpr double kOnFace = 1e-9;

bool whole(const World& w, int e) {
    const CutState& cs = w.cut_state;
    return (w.cuts.cut_of_element.empty() || w.cuts.cut_of_element[e] < 0) && (cs.queued.empty() || !cs.queued[e]);
}

/// Where material point m is now [m].
Vec3 where_now(const World& w, const MaterialPoint& m) {
    Vec3 x = Vec3::Zero();
    for (int a = 0; a < 3; ++a)
        x += m.bary[a] * w.nodes.position[w.elements.nodes[m.element][a]];
    return x;
}

}  // namespace

std::array<MaterialPoint, 2> tissue_at(const World& w, ElementBvh& bvh, const Vec3& tip, const Vec3& heel) {
    std::array<MaterialPoint, 2> found{};
    if (w.elements.dim != 2) return found;  // 3D: the paper's anchor in space (material_anchor.h)
    const CutState& cs = w.cut_state;
    bvh.ensure(mesh_view(w), cs.mean_edge);
    std::vector<int> candidates;
    for (int k = 0; k < 2; ++k) {
        const Vec3& p = k == 0 ? tip : heel;
        candidates.clear();
        bvh.query_ball(p, 0.0, candidates);
        std::sort(candidates.begin(), candidates.end());
        for (const int e : candidates) {
            if (e >= w.mesh_elements || !whole(w, e)) continue;
            const auto& n = w.elements.nodes[e];
            const auto& x = w.nodes.position;
            const std::array<Vec3, 3> X{x[n[0]], x[n[1]], x[n[2]]};
            const Vec3 b = triangle_barycentric(X, p);
            if (std::abs((b.x() * X[0] + b.y() * X[1] + b.z() * X[2] - p).z()) > kOnFace * cs.mean_edge) continue;  // out of the plane
            if (b.minCoeff() >= -kOnFace) {
                found[k] = {e, b};
                break;
            }
        }
    }
    return found;
}

void carry_anchor(World& w, int i) {
    CutState& cs = w.cut_state;
    if (i >= static_cast<int>(cs.anchor_material.size())) return;
    const std::array<MaterialPoint, 2>& m = cs.anchor_material[i];
    std::array<Vec3*, 2> end{&cs.anchor_tip[i], &cs.anchor_heel[i]};
    std::array<Vec3, 2> moved{Vec3::Zero(), Vec3::Zero()};
    std::array<bool, 2> in{false, false};
    for (int k = 0; k < 2; ++k)
        if (m[k].element >= 0 && whole(w, m[k].element)) in[k] = true, moved[k] = where_now(w, m[k]) - *end[k];
    for (int k = 0; k < 2; ++k) {
        if (in[k]) *end[k] += moved[k];
        else if (in[1 - k]) *end[k] += moved[1 - k];
    }
}

}  // namespace xcut
