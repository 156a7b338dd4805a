#pragma once
// What `xcut run` reports at its end, as text on the console and, with --summary FILE, as JSON for
// a batch runner: the run's final figures, its status (ok, input_error, numerical_error) and
// message, and the warnings it printed.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/world.h"

namespace xcut {

struct RunFigures {
    double time_s = 0.0, wall_s = 0.0, steps_per_s = 0.0;  ///< simulated and wall time [s]
    int steps = 0, free_dofs = 0, last_cg_iterations = 0;
    /// The largest |x - X| over the mesh's nodes (corners and mid-edge nodes: the tissue's own), not
    /// over the phantom DOF nodes, whose positions only extrapolate a cut side's field [m].
    double max_displacement_m = 0.0, kinetic_J = 0.0, elastic_J = 0.0;
    int elements_split = 0, enriched_nodes = 0, front_held_nodes = 0;  ///< XFEM
    double max_opening_m = 0.0;                                        ///< max |a_j|
    int snap_elements_split = 0, snap_nodes_snapped = 0;               ///< the snapping baseline
    int refactored_steps = 0, substepped_steps = 0;
    /// Once-linearized steps that gained energy and went on with Newton iterations (solver
    /// "newton": {"on_energy_gain"}: systems/solver/energy_check.h).
    int energy_newton_steps = 0;
    /// Pieces of tissue now (-1: the scene has no cutter), and the rest volumes of the pieces cuts
    /// freed, in order [m^3]; pieces_line is the console's line on them ("" if none).
    int pieces = -1;
    std::vector<double> freed_volumes_m3;
    std::string pieces_line;
};

RunFigures run_figures(const World& world, int steps, double wall_seconds);
/// The figures as the summary's JSON has them (the Python API's Simulation.figures()).
nlohmann::json figures_json(const RunFigures& f);
/// The console lines `done: ...`, `cut: ...` (and the warning on renewed factors and substeps).
void print_figures(const RunFigures& f, int max_substeps);

struct RunSummary {
    std::string scene, name, status = "ok", message;
    bool has_figures = false;
    RunFigures figures;
    std::vector<std::string> warnings;
};
/// Writes the summary as JSON; throws InputError naming `path` and --summary when it cannot.
void write_summary(const std::string& path, const RunSummary& summary);

}  // namespace xcut
