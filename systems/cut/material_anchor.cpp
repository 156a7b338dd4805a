#include "systems/cut/material_anchor.h"

#include <algorithm>
#include <cmath>

#include "engine/fragment_geometry.h"  // triangle_barycentric, in_fragment
#include "systems/cut/cut_system.h"    // mesh_view
#include "systems/cut/recut.h"         // corners, lines_of
#include "systems/xfem_queries.h"

namespace xcut {

namespace {

/// Tolerance [-] on a barycentric coordinate for a point on an element's face or edge.
constexpr double kOnFace = 1e-9;

bool whole(const World& w, int e) {
    const CutState& cs = w.cut_state;
    return (w.cuts.cut_of_element.empty() || w.cuts.cut_of_element[e] < 0) && (cs.queued.empty() || !cs.queued[e]);
}

/// The element whose nodes carry material point m: the mesh triangle, or its fragment's.
int carrier(const World& w, const MaterialPoint& m) {
    return m.fragment < 0 ? m.element : w.virtual_elements.element[m.fragment];
}

/// Barycentric coordinates of p in element e's current triangle (its nodes' positions); false if
/// p lies off its plane or outside it.
bool holds_now(const World& w, int e, const Vec3& p, Vec3& b) {
    const auto& n = w.elements.nodes[e];
    const auto& x = w.nodes.position;
    const std::array<Vec3, 3> X{x[n[0]], x[n[1]], x[n[2]]};
    b = triangle_barycentric(X, p);
    if (std::abs((b.x() * X[0] + b.y() * X[1] + b.z() * X[2] - p).z()) > kOnFace * w.cut_state.mean_edge) return false;
    return b.minCoeff() >= -kOnFace;
}

/// Whether fragment (virtual element) v of cut mesh triangle e holds the material at barycentric
/// coordinates b (the rest point they give lies in it, on or inside its boundary).
bool fragment_has(const World& w, int e, int v, const Vec3& b) {
    const int c = w.cuts.cut_of_element[e];
    const auto frags = fragments_of(w, c);
    if (std::find(frags.begin(), frags.end(), v) == frags.end()) return false;
    const std::array<Vec3, 3> X = corners(w, e);
    CutLine first;
    const std::span<const CutLine> lines = lines_in(w, c, first);
    return in_fragment(lines.data(), static_cast<int>(lines.size()), w.virtual_elements.mask[v], b.x() * X[0] + b.y() * X[1] + b.z() * X[2]);
}

/// Whether material point m is still where its element (fragment) puts it: the element whole, or,
/// cut when it was found, its fragment still holding it (not divided away by a later cut).
bool still_held(const World& w, const MaterialPoint& m) {
    if (m.element < 0) return false;
    if (m.fragment < 0) return whole(w, m.element);
    const auto& cut = w.cuts.cut_of_element;
    return !cut.empty() && cut[m.element] >= 0 && fragment_has(w, m.element, m.fragment, m.bary);
}

}  // namespace

Vec3 material_position(const World& w, const MaterialPoint& m) {
    Vec3 x = Vec3::Zero();
    const int e = carrier(w, m);
    for (int a = 0; a < 3; ++a) x += m.bary[a] * w.nodes.position[w.elements.nodes[e][a]];
    return x;
}

Vec3 material_rest(const World& w, const MaterialPoint& m) {
    const std::array<Vec3, 3> X = corners(w, m.element);
    return m.bary.x() * X[0] + m.bary.y() * X[1] + m.bary.z() * X[2];
}

MaterialPoint material_in(const World& w, int e, const Vec3& p) {
    Vec3 b;
    if (whole(w, e)) return holds_now(w, e, p, b) ? MaterialPoint{e, b, -1} : MaterialPoint{};
    const auto& cut = w.cuts.cut_of_element;
    if (!recut_allowed(w) || cut.empty() || cut[e] < 0) return {};  // queued: split this step
    for (const int v : fragments_of(w, cut[e]))
        if (holds_now(w, w.virtual_elements.element[v], p, b) && fragment_has(w, e, v, b)) return {e, b, v};
    return {};
}

std::array<MaterialPoint, 2> tissue_at(const World& w, ElementBvh& bvh, const Vec3& tip, const Vec3& heel,
                                       const BladeCut* entered) {
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
        for (int pass = entered && !entered->crossing.empty() ? 0 : 1; pass < 2 && found[k].element < 0; ++pass)
            for (const int e : candidates) {
                if (e >= w.mesh_elements || (pass == 0 && !entered->crossing.contains(e))) continue;
                found[k] = material_in(w, e, p);
                if (found[k].element >= 0) break;
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
        if (still_held(w, m[k])) in[k] = true, moved[k] = material_position(w, m[k]) - *end[k];
    for (int k = 0; k < 2; ++k) {
        if (in[k]) *end[k] += moved[k];
        else if (in[1 - k]) *end[k] += moved[1 - k];
    }
}

}  // namespace xcut
