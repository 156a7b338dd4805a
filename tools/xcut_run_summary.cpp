#include "tools/xcut_run_summary.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/error.h"
#include "systems/cut/pieces_system.h"
#include "systems/xfem_queries.h"

namespace xcut {

RunFigures run_figures(const World& w, int steps, double secs) {
    RunFigures f;
    const StepMetrics& m = w.metrics.current;
    f.time_s = w.time, f.wall_s = secs, f.steps = steps, f.steps_per_s = steps / std::max(secs, 1e-9);
    f.free_dofs = m.dofs, f.last_cg_iterations = m.cg_iterations, f.kinetic_J = m.kinetic_energy, f.elastic_J = m.elastic_energy;
    for (int i = 0; i < w.mesh_nodes; ++i)
        f.max_displacement_m = std::max(f.max_displacement_m, (w.nodes.position[i] - w.nodes.rest[i]).norm());
    f.elements_split = w.cuts.count(), f.enriched_nodes = w.enriched.count();
    f.front_held_nodes = static_cast<int>(std::count(w.enriched.front_fixed.begin(), w.enriched.front_fixed.end(), 1));
    if (w.cuts.count() > 0)
        for (int j = 0; j < w.mesh_nodes; ++j) f.max_opening_m = std::max(f.max_opening_m, enriched_displacement(w, j).norm());
    f.snap_elements_split = w.snap.elements_split, f.snap_nodes_snapped = w.snap.snaps;
    f.refactored_steps = w.metrics.refactored_steps, f.substepped_steps = w.metrics.substepped_steps;
    f.energy_newton_steps = w.metrics.energy_newton_steps;
    if ((w.present() & kPieces) != 0) f.pieces = w.pieces.count;
    for (const PieceEvent& e : w.pieces.log) f.freed_volumes_m3.push_back(e.volume);
    f.pieces_line = pieces_report(w);
    return f;
}

void print_figures(const RunFigures& f, int max_substeps) {
    if (f.refactored_steps > 0 || f.substepped_steps > 0)
        fmt::print(stderr, "warning: to reach the CG tolerance, of {} steps {} needed a renewed factor and {} substeps "
                           "(up to {} each); solve_flag and substeps in the metrics CSV say which\n",
                   f.steps, f.refactored_steps, f.substepped_steps, max_substeps);
    if (f.energy_newton_steps > 0)
        fmt::print("note: {} once-linearized steps (of {}) gained energy (the tissue turning fast for the time step) "
                   "and went on with Newton iterations (solver.newton.on_energy_gain; newton_iterations in the "
                   "metrics CSV says which)\n",
                   f.energy_newton_steps, f.steps);
    fmt::print("done: t = {:.4g} s in {:.3f} s wall ({:.1f} steps/s); free DOFs {}; last step {} CG iterations; "
               "max displacement {:.4g} m; kinetic {:.4g} J, elastic {:.4g} J\n",
               f.time_s, f.wall_s, f.steps_per_s, f.free_dofs, f.last_cg_iterations, f.max_displacement_m, f.kinetic_J,
               f.elastic_J);
    if (f.elements_split > 0)
        fmt::print("cut: {} elements split, {} enriched DOF nodes ({} held by the crack front), max opening |a_j| {:.4g} m\n",
                   f.elements_split, f.enriched_nodes, f.front_held_nodes, f.max_opening_m);
    if (!f.pieces_line.empty()) fmt::print("{}\n", f.pieces_line);
}

nlohmann::json figures_json(const RunFigures& f) {
    return {{"time_s", f.time_s}, {"wall_s", f.wall_s}, {"steps", f.steps}, {"steps_per_s", f.steps_per_s},
            {"free_dofs", f.free_dofs}, {"last_cg_iterations", f.last_cg_iterations},
            {"max_displacement_m", f.max_displacement_m}, {"kinetic_J", f.kinetic_J}, {"elastic_J", f.elastic_J},
            {"elements_split", f.elements_split}, {"enriched_nodes", f.enriched_nodes},
            {"front_held_nodes", f.front_held_nodes}, {"max_opening_m", f.max_opening_m},
            {"snap_elements_split", f.snap_elements_split}, {"snap_nodes_snapped", f.snap_nodes_snapped},
            {"refactored_steps", f.refactored_steps}, {"substepped_steps", f.substepped_steps},
            {"energy_newton_steps", f.energy_newton_steps},
 {"pieces", f.pieces}, {"freed_volumes_m3", f.freed_volumes_m3}};
}

void write_summary(const std::string& path, const RunSummary& s) {
    nlohmann::json j;
    j["scene"] = s.scene, j["name"] = s.name, j["status"] = s.status, j["message"] = s.message;
    j["warnings"] = s.warnings;
    if (s.has_figures) {
        j["figures"] = figures_json(s.figures);
    }
    std::ofstream out(path);
    out << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    if (!out) throw InputError(path, "--summary", "cannot write the summary file");
}

}  // namespace xcut
