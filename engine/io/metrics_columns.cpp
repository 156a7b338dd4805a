#include "engine/io/metrics_columns.h"

#include <fmt/format.h>

#include <algorithm>

namespace xcut {

std::vector<MetricColumn> metric_columns(const World& world, int& split_total) {
    const StepMetrics& m = world.metrics.current;
    std::vector<MetricColumn> c = {
        {"step", double(m.step), 'd'},
        {"time_s", m.time, 'g'},
        {"dt_s", m.dt, 'g'},
        {"dofs", double(m.dofs), 'd'},
        {"cg_iterations", double(m.cg_iterations), 'd'},
        {"cg_residual", m.cg_residual, 'r'},
        {"kinetic_J", m.kinetic_energy, 'e'},
        {"elastic_J", m.elastic_energy, 'e'},
        {"gravity_work_J", m.gravity_work, 'e'},
        {"step_ms", m.step_ms, 'f'},
        {"solve_flag", double(m.solve_flag), 'd'},
        {"substeps", double(m.substeps), 'd'},
        {"newton_iterations", double(m.newton_iterations), 'd'},
        {"preconditioner", double(m.preconditioner), 'd'},
        {"preconditioner_wait_ms", m.preconditioner_wait_ms, 'f'},
    };
    const std::vector<std::string>& systems = world.metrics.system_names;
    for (size_t i = 0; i < systems.size(); ++i)
        c.push_back({systems[i] + "_ms", i < m.system_ms.size() ? m.system_ms[i] : 0.0, 'f'});
    if ((world.present() & kPieces) != 0) c.push_back({"pieces", double(world.pieces.count), 'd'});
    if (world.tools.count() > 0) {
        // Delays of the splits queued in this step (the tail of the run-long list). elements_split
        // counts what the cutter applied (a queued split whose nodes an earlier cut already put on
        // one side is not one), so the column sums to the run's total.
        const CutState& cs = world.cut_state;
        const int total = world.cuts.count() + world.snap.elements_split;
        const int split_now = total - split_total;
        split_total = total;
        double sum = 0.0, max = 0.0;
        const size_t n = static_cast<size_t>(std::max(cs.elements_split, 0));
        for (size_t i = cs.delay_sim.size() - std::min(n, cs.delay_sim.size()); i < cs.delay_sim.size(); ++i)
            sum += cs.delay_sim[i], max = std::max(max, cs.delay_sim[i]);
        c.push_back({"quads", double(cs.quads_built), 'd'});
        c.push_back({"elements_tested", double(cs.elements_tested), 'd'});
        c.push_back({"crossings", double(cs.crossings_found), 'd'});
        c.push_back({"elements_split", double(split_now), 'd'});
        c.push_back({"cut_update_ms", cs.update_ms, 'f'});
        c.push_back({"crossing_delay_mean_s", n > 0 ? sum / n : 0.0, 's'});
        c.push_back({"crossing_delay_max_s", max, 's'});
        c.push_back({"enriched_nodes", double(world.enriched.count()), 'd'});
        // Each blade's cutting resistance (systems/cut/cutting_force.h): part of the tool's force.
        const ToolBodies& tb = world.tools;
        for (int i = 0; i < tb.count(); ++i) {
            if (!tb.has_blade[i]) continue;
            const bool known = i < static_cast<int>(tb.cutting_force.size());
            const Vec3 f = known ? tb.cutting_force[i] : Vec3::Zero();
            for (int k = 0; k < 3; ++k) c.push_back({fmt::format("{}_cut_f{}_N", tb.name[i], "xyz"[k]), f[k], 'e'});
            c.push_back({fmt::format("{}_depth_m", tb.name[i]), known ? tb.blade_depth[i] : 0.0, 'e'});
        }
    }
    if ((world.present() & kShapedTools) != 0) {
        // The tissue's reaction on each tool (zero before its first contact step).
        const ToolBodies& tb = world.tools;
        c.push_back({"contacts", double(world.contacts.count()), 'd'});
        for (int i = 0; i < tb.count(); ++i) {
            const bool known = i < static_cast<int>(tb.reaction_force.size());
            const Vec3 f = known ? tb.reaction_force[i] : Vec3::Zero(), t = known ? tb.reaction_torque[i] : Vec3::Zero();
            const std::string& n = tb.name[i];
            for (int k = 0; k < 3; ++k) c.push_back({fmt::format("{}_f{}_N", n, "xyz"[k]), f[k], 'e'});
            for (int k = 0; k < 3; ++k) c.push_back({fmt::format("{}_t{}_Nm", n, "xyz"[k]), t[k], 'e'});
        }
    }
    if ((world.present() & kGrasps) != 0) {
        // Each grasper's pull from the tissue it holds (zero while its jaws are open), and how many
        // skin vertices they hold (systems/grasp_system.h).
        const Grasps& g = world.grasps;
        for (int i = 0; i < g.count(); ++i) {
            if (!(g.radius[i] > 0.0)) continue;
            const std::string& n = world.tools.name[i];
            c.push_back({fmt::format("{}_held", n), double(g.vertex[i].size()), 'd'});
            for (int k = 0; k < 3; ++k) c.push_back({fmt::format("{}_grasp_f{}_N", n, "xyz"[k]), g.force[i][k], 'e'});
        }
    }
    return c;
}

std::string format_metric(const MetricColumn& column) {
    const double v = column.value;
    switch (column.format) {
        case 'd': return fmt::format("{}", static_cast<long long>(v));
        case 'r': return fmt::format("{:.3e}", v);
        case 'e': return fmt::format("{:.9e}", v);
        case 'f': return fmt::format("{:.4f}", v);
        case 's': return fmt::format("{:.6g}", v);
        default: return fmt::format("{:.9g}", v);
    }
}

}  // namespace xcut
