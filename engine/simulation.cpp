#include "engine/simulation.h"

#include <algorithm>

namespace xcut {

std::unique_ptr<Simulation> build_simulation(const Scene& scene, const Pipeline& pipeline, bool with_output,
                                             const std::string& replay_directory) {
    auto sim = std::make_unique<Simulation>();
    sim->world = build_world(scene);
    sim->devices = make_devices(sim->world, replay_directory);
    ToolBodies& tb = sim->world.tools;
    for (int i = 0; i < tb.count(); ++i) {  // start where the device is
        const Keyframe k = sim->devices[i]->pose(sim->world.time);
        tb.position[i] = k.position, tb.orientation[i] = k.orientation;
    }
    if (!with_output) sim->world.output.directory.clear();
    pipeline(scene, sim->scheduler, *sim);
    sim->scheduler.build(sim->world);
    if (!sim->world.output.directory.empty()) {
        sim->output = std::make_unique<OutputWriter>(sim->world);
        sim->output->write_frame(sim->world);
    }
    return sim;
}

void step_simulation(Simulation& sim) {
    sim.scheduler.step(sim.world);
    if (sim.output) sim.output->metrics_row(sim.world);
    if (sim.recorder) sim.recorder->record(sim.world);
    if (sim.haptics) sim.haptics->publish(sim.world);
    SolverSettings& s = sim.world.solver;
    if (s.realtime) s.dt = std::clamp(sim.world.metrics.current.step_ms * 1e-3, s.dt_min, s.dt_max);
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
