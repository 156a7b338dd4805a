#include "systems/cut/cutting_force.h"

#include <algorithm>
#include <cmath>

#include "systems/kernels/blade_pose.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/kernels/segment_clip.h"

namespace xcut {

namespace {

/// The edge's part inside one element: [s0, s1] of tip (0) -> heel (1), and its material.
struct EdgeInterval {
    double s0 = 0.0, s1 = 0.0;
    int material = 0;
    bool fresh = true;  ///< uncut material (or a tip element): the blade opens new surface here
};

/// XFEM cut c is still a tip element: the blade has not crossed all its split edges (progressive
/// front). An edge inside a cut element the blade has crossed fully is back in its own wound.
bool tip_element(const CutElements& ce, int c) {
    for (const int8_t k : ce.point_edge[c])
        if (k >= 0 && !((ce.crossed[c] >> k) & 1)) return true;
    return false;
}

/// Current vertex positions of force element f.
std::array<Vec3, 4> vertices(const World& w, int f) {
    std::array<Vec3, 4> x;
    const int npe = w.elements.nodes_per_element();
    for (int a = 0; a < 4; ++a) x[a] = a < npe ? w.nodes.position[w.elements.nodes[f][a]] : Vec3::Zero();
    return x;
}

/// One side of an XFEM cut inside a virtual element: n . (x - point) >= 0 (> 0 when `open`: the
/// lower side, so an edge lying in the cut counts once).
struct Side {
    Vec3 point, normal;
    bool open = false;
};

/// The side of XFEM cut c that virtual element v holds, in its vertices x [m]. The cut points sit on
/// the parent's edges at parameters taken in the rest shape; the element's own map carries them to
/// its current vertices.
Side side_of(const World& w, int c, int v, const std::array<Vec3, 4>& x) {
    const CutElements& ce = w.cuts;
    const int dim = w.elements.dim, e = ce.element[c];
    const auto& mesh_nodes = w.elements.nodes[e];
    std::array<Vec3, 4> p;
    int np = 0;
    for (int k = 0; k < 4 && ce.point_edge[c][k] >= 0; ++k) {
        const int* ends = edge_nodes(dim, ce.point_edge[c][k]);
        const Vec3 &X0 = w.nodes.rest[mesh_nodes[ends[0]]], &X1 = w.nodes.rest[mesh_nodes[ends[1]]];
        const double t = std::clamp((ce.points[c][k] - X0).dot(X1 - X0) / (X1 - X0).squaredNorm(), 0.0, 1.0);
        p[np++] = x[ends[0]] + t * (x[ends[1]] - x[ends[0]]);
    }
    const int8_t side = w.virtual_elements.side[v];
    Side out{p[0], Vec3::Zero(), side < 0};
    if (dim == 2) {
        const Vec3 d = np > 1 ? Vec3(p[1] - p[0]) : Vec3::UnitX();
        out.normal = Vec3(-d.y(), d.x(), 0.0);
    } else {  // the largest cross product of two chords: the points are coplanar up to the fit
        for (int j = 1; j < np; ++j)
            for (int k = j + 1; k < np; ++k) {
                const Vec3 n = (p[j] - p[0]).cross(p[k] - p[0]);
                if (n.squaredNorm() > out.normal.squaredNorm()) out.normal = n;
            }
    }
    double toward = 0.0;  // the side's own nodes lie on its side of the plane
    for (int a = 0; a < w.elements.nodes_per_element(); ++a)
        if (w.enriched.sign[mesh_nodes[a]] == side) toward += out.normal.dot(x[a] - out.point);
    if (toward < 0.0) out.normal = -out.normal;
    return out;
}

/// Appends force element f's part of the edge (tip -> heel), within `side` if given. 2D: the whole
/// [0, 1] if the tip is inside.
void clip_element(const World& w, int f, const Vec3& tip, const Vec3& heel, const Side* side, bool fresh,
                  std::vector<EdgeInterval>& out) {
    const std::array<Vec3, 4> x = vertices(w, f);
    double s0 = 0.0, s1 = 1.0;
    if (w.elements.dim == 2) {
        const double level = side ? side->normal.dot(tip - side->point) : 1.0;
        if (!in_triangle_xy(x, tip) || level < 0.0 || (side && side->open && level == 0.0)) return;
    } else {
        clip_to_tet(x, tip, heel, s0, s1);
        if (side && s0 <= s1) clip_to_half_space(tip, heel, side->point, side->normal, s0, s1, side->open);
        if (!(s1 > s0)) return;
    }
    out.push_back({s0, s1, w.elements.material[f], fresh});
}

/// The edge's parts inside the tissue, element by element, in the order of the BVH's candidates.
std::vector<EdgeInterval> edge_in_tissue(const World& w, ElementBvh& bvh, const Vec3& tip, const Vec3& heel) {
    std::vector<int> candidates;
    const bool flat = w.elements.dim == 2;  // the cutting point is the tip
    bvh.ensure({&w.elements, &w.nodes.position, w.mesh_elements, w.mesh_nodes}, w.cut_state.mean_edge);
    bvh.query_ball(flat ? tip : Vec3(0.5 * (tip + heel)), flat ? 0.0 : 0.5 * (heel - tip).norm(), candidates);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    std::vector<EdgeInterval> out;
    for (const int e : candidates) {
        const int c = e < static_cast<int>(w.cuts.cut_of_element.size()) ? w.cuts.cut_of_element[e] : -1;
        if (c >= 0) {
            const bool fresh = tip_element(w.cuts, c);
            for (const int v : w.cuts.virtual_element[c]) {
                if (v < 0) continue;
                const int f = w.virtual_elements.element[v];
                const Side side = side_of(w, c, v, vertices(w, f));
                clip_element(w, f, tip, heel, &side, fresh, out);
            }
        } else if (e < static_cast<int>(w.snap.pieces.size()) && !w.snap.pieces[e].empty()) {
            for (const int f : w.snap.pieces[e])
                if (w.elements.weight[f] > 0.0) clip_element(w, f, tip, heel, nullptr, false, out);
        } else if (w.elements.weight[e] > 0.0) {
            clip_element(w, e, tip, heel, nullptr, true, out);
        }
        if (flat && !out.empty()) break;  // a point on a shared edge counts once
    }
    // Elements meet on faces: an edge lying in one (a blade on a grid plane) is in both. Each part
    // of the edge counts once, for the first interval (by start, then element order) that holds it.
    std::stable_sort(out.begin(), out.end(), [](const EdgeInterval& a, const EdgeInterval& b) { return a.s0 < b.s0; });
    double covered = -1.0;
    std::vector<EdgeInterval> once;
    for (EdgeInterval k : out) {
        k.s0 = std::max(k.s0, covered);
        if (!(k.s1 > k.s0) && !flat) continue;
        covered = std::max(covered, k.s1);
        once.push_back(k);
    }
    return once;
}

/// u / max(|u|, kCuttingSpeedFloor): its direction, scaled down linearly below the floor.
Vec3 regularized_direction(const Vec3& u) { return u / std::max(u.norm(), kCuttingSpeedFloor); }

}  // namespace

void compute_cutting_forces(World& w, ElementBvh& bvh) {
    ToolBodies& tb = w.tools;
    const int n = tb.count();
    tb.cutting_force.assign(n, Vec3::Zero());
    tb.cutting_torque.assign(n, Vec3::Zero());
    tb.blade_depth.assign(n, 0.0);
    w.cut_state.stab_travel.resize(n, 0.0);
    if (w.cut_state.mean_edge == 0.0 && w.elements.count() > 0)
        w.cut_state.mean_edge = mean_edge_length(w.elements, w.nodes.rest, w.mesh_elements);
    const double dt = w.solver.dt;
    for (int i = 0; i < n; ++i) {
        if (!tb.has_blade[i]) continue;
        Vec3 tip, heel, tip0, heel0;
        blade_in_world(tb, i, tip, heel);
        tip0 = tip, heel0 = heel;
        if (i < static_cast<int>(tb.sweep.size()) && !tb.sweep[i].empty()) blade_at(tb, i, tb.sweep[i].front(), tip0, heel0);
        const Vec3 v_tip = dt > 0.0 ? Vec3((tip - tip0) / dt) : Vec3::Zero();
        const Vec3 v_heel = dt > 0.0 ? Vec3((heel - heel0) / dt) : Vec3::Zero();
        const Vec3 along = (heel - tip).normalized();
        const double edge_length = (heel - tip).norm();
        const bool flat = w.elements.dim == 2;
        for (const EdgeInterval& k : edge_in_tissue(w, bvh, tip, heel)) {
            const Material& m = w.materials.list[k.material];
            const double length = flat ? m.thickness : (k.s1 - k.s0) * edge_length;
            const double s = flat ? 0.0 : 0.5 * (k.s0 + k.s1);
            const Vec3 v = (1.0 - s) * v_tip + s * v_heel;
            const Vec3 across = flat ? v : Vec3(v - v.dot(along) * along);
            const double toughness = k.fresh ? m.toughness : 0.0;
            const Vec3 f = -toughness * length * regularized_direction(across) -
                           m.blade_friction * length * regularized_direction(v);
            tb.cutting_force[i] += f;
            tb.cutting_torque[i] += (tip + s * (heel - tip) - tb.position[i]).cross(f);
            tb.blade_depth[i] += length;
        }
        // A stab: the edge, in the tissue, moving along itself (its motion across the edge under a
        // tenth of its speed) sweeps no surface and cuts nothing; the run's end says how far.
        const Vec3 v_mid = 0.5 * (v_tip + v_heel);
        const double speed = v_mid.norm(), across = (v_mid - v_mid.dot(along) * along).norm();
        if (!flat && tb.blade_depth[i] > 0.0 && speed > kCuttingSpeedFloor && across < 0.1 * speed)
            w.cut_state.stab_travel[i] += speed * dt;
    }
    tb.reaction_force = tb.cutting_force;
    tb.reaction_torque = tb.cutting_torque;
}

SystemDesc cutting_force_system(std::shared_ptr<ElementBvh> bvh) {
    SystemDesc s{"CuttingForceSystem", kNodes | kElements | kMaterials | kTools | kCutState, kTools | kCutState,
                 [bvh](World& w) { compute_cutting_forces(w, *bvh); }};
    return s.also_reads(kXfem | kSnap);  // the virtual elements' sides, the snapping pieces
}

}  // namespace xcut
