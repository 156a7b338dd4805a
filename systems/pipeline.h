#pragma once
// xcut's pipeline: the one place that says which systems a step runs and in what order (paper §3,
// Fig. 2; docs/architecture.md draws it). The engine's step loop (engine/simulation.h) runs whatever
// pipeline it is handed; this is the one `xcut`, the tests and the benchmarks hand it.
//
//   ToolSystem → CutSystem → ScriptedCutSystem → EnrichmentSystem | SnapCutSystem → PiecesSystem
//     → ForceSystem
//     → RebindSystem → CollisionSystem → SolverSystem → WatchdogSystem → MappingSystem → OutputSystem
#include <memory>
#include <string>

#include "engine/simulation.h"
#include "systems/step_term.h"

namespace xcut {

/// Builds the scene's visual and collision surfaces, the cut search and the enrichment state the
/// scene needs, and adds every system of the pipeline to `scheduler` in order.
void xcut_pipeline(const Scene& scene, Scheduler& scheduler, Simulation& sim);

/// The terms of xcut's implicit step, in order (systems/step_term.h): the ForceSystem's elastic
/// term, then the CollisionSystem's contacts. What the SolverSystem is handed, and what a test or a
/// study that calls the solver directly hands it.
StepOperator xcut_step_terms();

/// build_simulation with xcut_pipeline: the simulation `xcut run` steps.
std::unique_ptr<Simulation> make_simulation(const Scene& scene, bool with_output = true,
                                            const std::string& replay_directory = "");

}  // namespace xcut
