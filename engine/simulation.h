#pragma once
// A scene turned into a world plus its schedule, and the step loop: what `xcut run` steps, and what
// tests and benchmarks drive directly. The engine knows no concrete system: which systems run, and
// in what order, is a Pipeline handed in (xcut's own is composed in systems/pipeline.h).
#include <functional>
#include <memory>

#include "engine/devices/device.h"
#include "engine/devices/haptic_loop.h"
#include "engine/io/output.h"
#include "engine/io/scene.h"
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
    std::string replay_directory;                      ///< the session being replayed, if any
    std::vector<double> replay_dt;                     ///< its recorded dt per step [s]; empty: none
    int steps_done = 0;
};

/// Prepares what the systems need beyond the world (surfaces, search structures) and adds the
/// systems to the scheduler in pipeline order.
using Pipeline = std::function<void(const Scene& scene, Scheduler& scheduler, Simulation& sim)>;

/// Builds the world from the scene, places the tools where their devices start, and registers the
/// pipeline's systems; the scheduler keeps those whose components the scene holds. `with_output`
/// false: no files written (tests, benchmarks). `replay_directory`: drive the tools from a recorded
/// session (engine/devices/device.h) instead of the scene's trajectories.
std::unique_ptr<Simulation> build_simulation(const Scene& scene, const Pipeline& pipeline, bool with_output = true,
                                             const std::string& replay_directory = "");
/// Starts the haptic loop over the simulation's devices (published to after each step) when `asked`
/// or when a device renders force to a person (ToolDevice::wants_force: a network haptic device);
/// null otherwise. Stop it before the simulation goes.
std::unique_ptr<HapticLoop> start_haptics(Simulation& sim, bool asked);
/// One step; in real-time mode, the next dt follows the measured step time (paper §4.3).
void step_simulation(Simulation& sim);
/// Runs `steps` steps, with a progress bar on a terminal.
void run_simulation(Simulation& sim, int steps, bool progress);

}  // namespace xcut
