#include "engine/simulation.h"

#include <fmt/format.h>

#include <algorithm>

#include "engine/error.h"
#include "engine/io/scene_checks.h"

namespace xcut {

std::unique_ptr<Simulation> build_simulation(const Scene& scene, const Pipeline& pipeline, bool with_output,
                                             const std::string& replay_directory) {
    auto sim = std::make_unique<Simulation>();
    sim->world = build_world(scene);
    sim->devices = make_devices(sim->world, scene.devices, replay_directory);
    sim->replay_directory = replay_directory;
    if (!replay_directory.empty()) sim->replay_dt = read_session_steps(replay_directory);
    ToolBodies& tb = sim->world.tools;
    for (int i = 0; i < tb.count(); ++i) {  // start where the device is
        const Keyframe k = sim->devices[i]->pose(sim->world.time);
        tb.position[i] = k.position, tb.orientation[i] = k.orientation;
    }
    if (!with_output) sim->world.output.directory.clear();
    pipeline(scene, sim->scheduler, *sim);
    sim->scheduler.build(sim->world);
    if (!sim->world.output.directory.empty()) {
        check_output_volume(scene, sim->world, scene.steps);  // before the first file is written
        sim->output = std::make_unique<OutputWriter>(sim->world);
        sim->output->write_frame(sim->world);
    }
    return sim;
}

std::unique_ptr<HapticLoop> start_haptics(Simulation& sim, bool asked) {
    std::vector<ToolDevice*> devices;
    for (auto& d : sim.devices) devices.push_back(d.get());
    if (!asked && std::none_of(devices.begin(), devices.end(), [](ToolDevice* d) { return d->wants_force(); }))
        return nullptr;
    auto haptics = std::make_unique<HapticLoop>(devices);
    sim.haptics = haptics.get();
    haptics->start();
    return haptics;
}

void step_simulation(Simulation& sim) {
    SolverSettings& s = sim.world.solver;
    if (!sim.replay_dt.empty()) {  // a recorded session: each step's dt as it was taken
        if (sim.steps_done >= static_cast<int>(sim.replay_dt.size()))
            throw InputError(sim.replay_directory + "/steps.csv", fmt::format("step {}", sim.steps_done + 1),
                             fmt::format("the recorded session has {} steps; replay at most that many (--steps)",
                                         sim.replay_dt.size()));
        s.dt = sim.replay_dt[sim.steps_done];
    }
    sim.scheduler.step(sim.world);
    ++sim.steps_done;
    if (sim.output) sim.output->metrics_row(sim.world);
    if (sim.recorder) sim.recorder->record(sim.world);
    if (sim.haptics) sim.haptics->publish(sim.world);
    // Real time (paper §4.3): the next dt follows the measured step time; a replay takes the recorded one.
    if (s.realtime && sim.replay_dt.empty())
        s.dt = std::clamp(sim.world.metrics.current.step_ms * 1e-3, s.dt_min, s.dt_max);
}

void run_simulation(Simulation& sim, int steps, bool progress) {
    ProgressBar bar("run", progress ? steps : 0);
    for (int i = 0; i < steps; ++i) {
        step_simulation(sim);
        bar.update(i + 1);
    }
    bar.finish();
    if (sim.output) sim.output->finish();
}

}  // namespace xcut
