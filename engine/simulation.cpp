#include "engine/simulation.h"

#include <algorithm>

#include "systems/collision_system.h"
#include "systems/cut_system.h"
#include "systems/enrichment_system.h"
#include "systems/force_system.h"
#include "systems/mapping_system.h"
#include "systems/scripted_cut_system.h"
#include "systems/snap_cut_system.h"
#include "systems/tool_system.h"
#include "systems/solver_system.h"

namespace xcut {

void register_systems(Scheduler& scheduler, Simulation& sim) {
    scheduler.add(tool_system([&sim](int i, double t) { return sim.devices[i]->pose(t); }));
    auto bvh = std::make_shared<ElementBvh>();
    const bool blades = (sim.world.present() & kCutEvents) != 0;
    if (blades && sim.world.tools.count() > 0) prepare_cut_search(sim.world, *bvh);
    if (blades) prepare_enrichment(sim.world);
    scheduler.add(cut_system(bvh));
    scheduler.add(scripted_cut_system());
    scheduler.add(sim.world.snap.enabled ? snap_cut_system(sim.world) : enrichment_system());
    scheduler.add(force_system());
    scheduler.add(collision_system(make_collision_model()));
    scheduler.add(solver_system());
    scheduler.add(mapping_system());
    scheduler.add({"OutputSystem", kNodes | kElements | kOutput, 0, [&sim](World& w) {
                       if (sim.output) sim.output->frame_if_due(w);
                   }});
}

std::unique_ptr<Simulation> make_simulation(const Scene& scene, bool with_output, const std::string& replay_directory) {
    auto sim = std::make_unique<Simulation>();
    sim->world = build_world(scene);
    sim->devices = make_devices(sim->world, replay_directory);
    ToolBodies& tb = sim->world.tools;
    for (int i = 0; i < tb.count(); ++i) {  // start where the device is
        const Keyframe k = sim->devices[i]->pose(sim->world.time);
        tb.position[i] = k.position, tb.orientation[i] = k.orientation;
    }
    if (scene.visual_subdivisions >= 0) build_surface(sim->world, sim->world.visual, scene.visual_subdivisions);
    if (scene.collision_subdivisions >= 0)
        build_surface(sim->world, sim->world.collision, scene.collision_subdivisions);
    if (!with_output) sim->world.output.directory.clear();
    register_systems(sim->scheduler, *sim);
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
