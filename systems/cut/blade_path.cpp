// The CutSystem's step: each bladed tool's path over the step (ToolBodies::sweep) becomes the
// collision quads process_cut_quad takes (systems/cut/cut_system.h): a quad from the anchor to each
// point of the path the blade has moved a threshold from it, and where the blade stops.
#include <algorithm>

#include "systems/cut/cut_system.h"
#include "systems/cut/material_anchor.h"
#include "systems/cut/recut.h"
#include "systems/cut/stem_2d.h"
#include "systems/cut/stem_3d.h"
#include "systems/kernels/blade_pose.h"
#include "systems/kernels/intersection.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/xfem_queries.h"

namespace xcut {
namespace {

/// Appends the blade tip's segment to b (world, 2D; from the path's last point, or `start` for its
/// first) to tool i's path, and notes the time the path
/// first closes a loop: it crosses an earlier segment of itself (not the one before, which it
/// continues), or another blade's path at a second point (two arcs crossing at both tips).
void note_loop(World& w, int i, const Vec3& start, const Vec3& b) {
    CutState& cs = w.cut_state;
    if (static_cast<int>(cs.path.size()) <= i) {
        cs.path.resize(i + 1), cs.path_time.resize(i + 1, w.time);
        cs.loop_time.resize(i + 1, -1.0), cs.loop_with.resize(i + 1, -1);
    }
    std::vector<Vec3>& path = cs.path[i];
    if (path.empty()) cs.path_time[i] = w.time, path.push_back(start);
    // The path in space: from where the blade was (not the anchor, which moves with the tissue).
    const Vec3 a = path.back();
    const auto closes = [&](int j) { cs.loop_time[i] = w.time, cs.loop_with[i] = j; };
    for (size_t k = 0; cs.loop_time[i] < 0.0 && k + 2 < path.size(); ++k)
        if (segment_segment_2d(path[k], path[k + 1], a, b)) closes(i);
    for (int j = 0; j < static_cast<int>(cs.path.size()) && cs.loop_time[i] < 0.0; ++j) {
        if (j == i) continue;
        std::vector<Vec3>& meet = cs.paths_meet[{std::min(i, j), std::max(i, j)}];
        const std::vector<Vec3>& other = cs.path[j];
        for (size_t k = 0; k + 1 < other.size(); ++k) {
            const std::optional<double> s = segment_segment_2d(other[k], other[k + 1], a, b);
            if (!s) continue;
            const Vec3 x = other[k] + *s * (other[k + 1] - other[k]);
            // One crossing met at a path's vertex is found on both its segments: once.
            if (std::none_of(meet.begin(), meet.end(), [&](const Vec3& m) { return (m - x).norm() < 0.25 * cs.mean_edge; }))
                meet.push_back(x);
        }
        if (meet.size() >= 2) closes(j);
    }
    path.push_back(b);
}

/// The blade at one point of its path: its edge, and its face from the edge to its back (zero: none) [m].
struct BladeAt {
    Vec3 tip, heel, back;
};

/// The quad the edge swept from the anchor to `b`, and with a face, the face at `b` (it cuts what it
/// passes through: a stab pushed along the edge sweeps no surface with its edge).
void cut_to(World& w, ElementBvh& bvh, int i, const BladeAt& b) {
    CutState& cs = w.cut_state;
    if (w.elements.dim == 2) {
        if (static_cast<int>(cs.path.size()) <= i || cs.path[i].empty()) {  // the path begins: in which element
            if (static_cast<int>(cs.blade.size()) <= i) cs.blade.resize(i + 1);
            cs.blade[i].start_point = tissue_at(w, bvh, cs.anchor_tip[i], cs.anchor_heel[i])[0];
            cs.blade[i].start_element = cs.blade[i].start_point.element;
        }
        note_loop(w, i, cs.anchor_tip[i], b.tip);
    }
    const CutQuad face{{b.tip, b.heel, b.heel + b.back, b.tip + b.back}};
    process_cut_quad(w, bvh, CutQuad{{cs.anchor_tip[i], cs.anchor_heel[i], b.heel, b.tip}}, i,
                     b.back == Vec3::Zero() ? nullptr : &face);
    cs.anchor_tip[i] = b.tip, cs.anchor_heel[i] = b.heel;
    cs.anchor_material[i] = tissue_at(w, bvh, b.tip, b.heel, &cs.blade[i]);
    cs.since_anchor[i].clear();
}

/// Whether the blade turned since its last quad: an edge it passed lies off the straight sweep from
/// the anchor to `b` by more than `turn` [m].
bool turned_since_anchor(const CutState& cs, int i, const BladeAt& b, double turn) {
    return std::any_of(cs.since_anchor[i].begin(), cs.since_anchor[i].end(), [&](const std::array<Vec3, 2>& e) {
        return edge_off_sweep(e[0], e[1], cs.anchor_tip[i], cs.anchor_heel[i], b.tip, b.heel, turn);
    });
}

/// A blade stopped at `end` inside cut elements it entered across their cuts (2D): each crossed on
/// one edge is cut again from that crossing to `end` (stem_event, its segment the other way), so a
/// stem that crosses a wound and stops past it inside the element (an arc's overshoot at the tip of
/// a fusiform excision) divides the fragment it crossed. Its crossing stays: if the blade goes on
/// and leaves the element, the cut along the whole chord divides what the stem did not (its line is
/// the stem's: record_recut), so a pause inside the element loses nothing.
void end_stems(World& w, int tool, const Vec3& end) {
    CutState& cs = w.cut_state;
    if (static_cast<int>(cs.blade.size()) <= tool || !recut_allowed(w)) return;
    const BladeCut& bc = cs.blade[tool];
    std::vector<int> entered;  // in element order (the map's is not fixed)
    for (const auto& [e, c] : bc.crossing)
        if (w.cuts.cut_of_element[e] >= 0 && !c.split && __builtin_popcount(c.mask) == 1) entered.push_back(e);
    std::sort(entered.begin(), entered.end());
    for (int e : entered) {
        const ElementCrossings& c = bc.crossing.at(e);
        if (c.turn.element >= 0) queue_stem(w, e, c, material_position(w, c.turn), tool);  // a dip: where it turned
        else queue_stem(w, e, c, end, tool, true);
    }
}

/// Cuts along one blade's path over the step: a quad from the anchor to each point of the path the
/// blade has moved `threshold` away from it; then, if the blade has stopped (it ends the step where
/// it ended the last), the stretch left shorter than the threshold, so an incision ends where the
/// blade ends.
void sweep_blade(World& w, ElementBvh& bvh, int i, const std::vector<BladeAt>& path, double threshold) {
    CutState& cs = w.cut_state;
    const auto moved = [&](const BladeAt& b) {
        return std::max((b.tip - cs.anchor_tip[i]).norm(), (b.heel - cs.anchor_heel[i]).norm());
    };
    // A turn short of the threshold: a quad to the last sample before the sweep strays
    // (cuts_at_turns), so the elements at the turn's apex are crossed, not cut along its chord.
    const double turn = cuts_at_turns(w) ? kTurnFraction * threshold : 0.0;
    for (size_t k = path.size() > 1 ? 1 : 0; k < path.size(); ++k) {
        if (turn > 0.0 && !cs.since_anchor[i].empty() && turned_since_anchor(cs, i, path[k], turn)) {
            const std::array<Vec3, 2> last = cs.since_anchor[i].back();
            if (std::max((last[0] - cs.anchor_tip[i]).norm(), (last[1] - cs.anchor_heel[i]).norm()) > 1e-6 * threshold)
                cut_to(w, bvh, i, BladeAt{last[0], last[1], path[k > 0 ? k - 1 : k].back});
            cs.since_anchor[i].clear();
        }
        if (moved(path[k]) >= threshold) cut_to(w, bvh, i, path[k]);
        else if (turn > 0.0) cs.since_anchor[i].push_back({path[k].tip, path[k].heel});
    }
    const BladeAt& end = path.back();
    const bool stopped = end.tip == cs.last_tip[i] && end.heel == cs.last_heel[i];
    cs.last_tip[i] = end.tip, cs.last_heel[i] = end.heel;
    if (!stopped) cs.ended[i] = 0;
    const double left = moved(end);
    // The step the blade stopped in: its stems are made though no stretch is left (its last quad
    // ended where it stopped), else a loop's end inside the element past a cross-cut met nothing.
    if (stopped && !cs.ended[i] && left < threshold) {
        if (left > 1e-6 * threshold) cut_to(w, bvh, i, end);
        // Stopped beside a wound it never met (within the join, across an edge): drawn on to it,
        // its stems made there, its anchor left where it stopped (a blade that goes on starts there).
        Vec3 to, tip = end.tip;
        const MaterialPoint& m = cs.anchor_material[i][0].element >= 0 ? cs.anchor_material[i][0] : cs.anchor_material[i][1];
        const auto in = cs.blade[i].crossing.find(m.element);
        const uint8_t entered = in == cs.blade[i].crossing.end() ? 0 : in->second.mask;
        const bool beside = w.elements.dim == 2 && recut_allowed(w) && wound_beside(w, m, entered, to);
        if (beside) cut_to(w, bvh, i, BladeAt{to, to + (end.heel - end.tip), end.back}), tip = to;
        if (w.elements.dim == 2) close_at_start(w, i);
        end_stems(w, i, tip);
        if (beside) {
            cs.anchor_tip[i] = end.tip, cs.anchor_heel[i] = end.heel;
            cs.anchor_material[i] = tissue_at(w, bvh, end.tip, end.heel, &cs.blade[i]);
        }
        cs.ended[i] = 1;
    }
}

}  // namespace

void run_cut_system(World& w, ElementBvh& bvh) {
    CutState& cs = w.cut_state;
    cs.quads.clear();
    cs.quads_built = cs.elements_tested = cs.crossings_found = cs.elements_split = 0;
    cs.update_ms = 0.0;
    if (cs.mean_edge == 0.0) cs.mean_edge = mean_edge_length(w.elements, w.nodes.rest, w.mesh_elements);
    const bool fronts = w.elements.dim == 3 && w.tips.follow_radius >= 0.0;
    const double threshold = cs.threshold > 0.0 ? cs.threshold : fronts ? kFrontQuadFraction * cs.mean_edge : cs.mean_edge;
    const ToolBodies& tb = w.tools;
    cs.anchored.resize(tb.count(), 0);
    cs.anchor_tip.resize(tb.count());
    cs.anchor_heel.resize(tb.count());
    cs.last_tip.resize(tb.count());
    cs.last_heel.resize(tb.count());
    cs.ended.resize(tb.count(), 0);
    cs.since_anchor.resize(tb.count());
    cs.blade.resize(tb.count());
    cs.anchor_material.resize(tb.count());
    for (int i = 0; i < tb.count(); ++i) {
        if (!tb.has_blade[i]) continue;
        // The blade's path over the step (ToolBodies::sweep), or only where it is now.
        std::vector<BladeAt> path;
        if (i < static_cast<int>(tb.sweep.size()) && !tb.sweep[i].empty()) {
            for (const Keyframe& k : tb.sweep[i]) {
                BladeAt b;
                blade_at(tb, i, k, b.tip, b.heel);
                b.back = blade_back_at(tb, i, k.orientation);
                path.push_back(b);
            }
        } else {
            BladeAt b;
            blade_in_world(w.tools, i, b.tip, b.heel);
            b.back = blade_back_at(tb, i, tb.orientation[i]);
            path.push_back(b);
        }
        if (!cs.anchored[i]) {
            cs.anchored[i] = 1, cs.anchor_tip[i] = path.front().tip, cs.anchor_heel[i] = path.front().heel;
            cs.last_tip[i] = path.front().tip, cs.last_heel[i] = path.front().heel;
        }
        carry_anchor(w, i);
        if (w.elements.dim == 2 && recut_allowed(w)) stem_at_start(w, i);
        sweep_blade(w, bvh, i, path, threshold);
    }
}

void prepare_cut_search(World& w, ElementBvh& bvh) {
    if (w.cut_state.mean_edge == 0.0) w.cut_state.mean_edge = mean_edge_length(w.elements, w.nodes.rest, w.mesh_elements);
    bvh.build(mesh_view(w), w.cut_state.mean_edge);
}

SystemDesc cut_system(std::shared_ptr<ElementBvh> bvh) {
    SystemDesc s{"CutSystem", kNodes | kElements | kTools | kCutEvents, kCutEvents | kCutState,
                 [bvh](World& w) { run_cut_system(w, *bvh); }};
    return s.also_reads(kXfem);  // an element already cut is not split again
}

}  // namespace xcut
