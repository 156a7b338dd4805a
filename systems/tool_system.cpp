#include "systems/tool_system.h"

#include <algorithm>

#include "engine/trajectory.h"
#include "systems/kernels/blade_pose.h"
#include "systems/kernels/mesh_measures.h"
#include "systems/xfem_queries.h"

namespace xcut {

namespace {

/// How far the blade of tool i moves from pose a to pose b [m]: the larger of its ends' moves.
double blade_move(const ToolBodies& tb, int i, const Keyframe& a, const Keyframe& b) {
    Vec3 ta, ha, tb_, hb;
    blade_at(tb, i, a, ta, ha);
    blade_at(tb, i, b, tb_, hb);
    return std::max((tb_ - ta).norm(), (hb - ha).norm());
}

/// Whether the blade at pose `mid` lies more than `turn` off its straight sweep from a to b.
bool turned(const ToolBodies& tb, int i, const Keyframe& a, const Keyframe& mid, const Keyframe& b, double turn) {
    Vec3 ta, ha, tm, hm, tb_, hb;
    blade_at(tb, i, a, ta, ha), blade_at(tb, i, mid, tm, hm), blade_at(tb, i, b, tb_, hb);
    return edge_off_sweep(tm, hm, ta, ha, tb_, hb, turn);
}

/// Appends to `out` the samples strictly after a up to and including b, bisecting while the blade
/// moves more than `spacing` between neighbours, or (turn > 0) while it lies more than `turn` off
/// its straight sweep halfway between them, down to a tenth of `spacing` (and while the sample
/// budget lasts).
void sample_between(const ToolBodies& tb, int i, const Keyframe& a, const Keyframe& b, double spacing, double turn,
                    const ToolPoseSource& source, std::vector<Keyframe>& out) {
    const double mid_time = 0.5 * (a.time + b.time), move = blade_move(tb, i, a, b);
    if ((move > spacing || (turn > 0.0 && move > turn)) && mid_time > a.time && mid_time < b.time &&
        static_cast<int>(out.size()) + 2 <= kMaxSweepSamples) {
        Keyframe mid = source(i, mid_time);
        mid.time = mid_time;
        if (move > spacing || turned(tb, i, a, mid, b, turn)) {
            sample_between(tb, i, a, mid, spacing, turn, source, out);
            sample_between(tb, i, mid, b, spacing, turn, source, out);
            return;
        }
    }
    out.push_back(b);
}

/// The sampling distance of blade sweeps: the cut threshold, or the mean edge length [m].
double sweep_spacing(World& world) {
    CutState& cs = world.cut_state;
    if (cs.threshold > 0.0) return cs.threshold;
    if (cs.mean_edge == 0.0 && world.elements.count() > 0) cs.mean_edge = mean_edge_length(world.elements, world.nodes.rest, world.mesh_elements);
    return cs.mean_edge;
}

}  // namespace

void advance_tools(World& world, double t) {
    advance_tools(world, t, [&world](int i, double s) { return sample_trajectory(world.tools.trajectory[i], s); });
}

void advance_tools(World& world, double t, const ToolPoseSource& source) {
    ToolBodies& tb = world.tools;
    const double dt = t - world.time;
    tb.velocity.resize(tb.count(), Vec3::Zero());
    tb.pose_time.resize(tb.count(), world.time);
    tb.sweep.resize(tb.count());
    const bool blades = std::any_of(tb.has_blade.begin(), tb.has_blade.end(), [](uint8_t b) { return b != 0; });
    const double spacing = blades ? sweep_spacing(world) : 0.0;
    const double turn = blades && cuts_at_turns(world) ? kTurnFraction * spacing : 0.0;
    for (int i = 0; i < tb.count(); ++i) {
        Keyframe start;
        start.time = tb.pose_time[i], start.position = tb.position[i], start.orientation = tb.orientation[i];
        Keyframe k = source(i, t);
        k.time = t;
        std::vector<Keyframe>& sweep = tb.sweep[i];
        sweep.assign(1, start);
        if (i < static_cast<int>(tb.has_blade.size()) && tb.has_blade[i] && spacing > 0.0 && t > start.time) sample_between(tb, i, start, k, spacing, turn, source, sweep);
        else sweep.push_back(k);
        tb.velocity[i] = dt > 0.0 ? Vec3((k.position - tb.position[i]) / dt) : Vec3::Zero();
        tb.position[i] = k.position;
        tb.orientation[i] = k.orientation;
        tb.pose_time[i] = t;
    }
}

SystemDesc tool_system(ToolPoseSource source) {
    return {"ToolSystem", kTools, kTools, [source](World& w) { advance_tools(w, w.time + w.solver.dt, source); }};
}

}  // namespace xcut
