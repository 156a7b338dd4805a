#pragma once
// A scene turned into a world plus its schedule: what `xcut run` steps, and what tests and
// benchmarks drive directly.
#include <memory>

#include "engine/device.h"
#include "engine/haptic_loop.h"
#include "engine/output.h"
#include "engine/scene.h"
#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

struct Simulation {
    World world;
    Scheduler scheduler;
    std::unique_ptr<OutputWriter> output;   ///< null when the scene writes no output
    std::vector<std::unique_ptr<ToolDevice>> devices;  ///< one per tool: where its pose comes from
    std::unique_ptr<SessionRecorder> recorder;        ///< records the tools' poses when set
    HapticLoop* haptics = nullptr;                     ///< published to after each step when set
};

/// Builds the world and registers every system in pipeline order; the scheduler keeps those whose
/// components the scene holds. `with_output` false: no files written (tests, benchmarks).
/// `replay_directory`: drive the tools from a recorded session (engine/device.h) instead of the
/// scene's trajectories.
std::unique_ptr<Simulation> make_simulation(const Scene& scene, bool with_output = true,
                                            const std::string& replay_directory = "");
/// Registers the systems of the pipeline (DESIGN.md "One step") on a scheduler.
void register_systems(Scheduler& scheduler, Simulation& sim);
/// One step; in real-time mode, the next dt follows the measured step time (paper §4.3).
void step_simulation(Simulation& sim);
/// Runs `steps` steps, with a progress bar on a terminal.
void run_simulation(Simulation& sim, int steps, bool progress);

}  // namespace xcut
