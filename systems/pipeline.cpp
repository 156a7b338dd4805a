#include "systems/pipeline.h"

#include <fmt/format.h>

#include "engine/error.h"

#include "systems/collision_system.h"
#include "systems/cut/crack_tip_system.h"
#include "systems/cut/cut_system.h"
#include "systems/cut/cutting_force.h"
#include "systems/cut/enrichment_system.h"
#include "systems/cut/pieces_system.h"
#include "systems/force_system.h"
#include "systems/grasp_system.h"
#include "systems/solver/linear_solver.h"
#include "systems/surface/mapping_system.h"
#include "systems/cut/scripted_cut_system.h"
#include "systems/cut/scripted_front_system.h"
#include "systems/cut/snap_cut_system.h"
#include "systems/solver/solver_system.h"
#include "systems/tool_system.h"
#include "systems/watchdog_system.h"

namespace xcut {
namespace {

/// The scripted cuts' fronts, found on the mesh at rest before the run (a cut whose polygon ends
/// nowhere in the tissue, or with a corner in it, is the scene's error).
void check_front_geometry(const Scene& scene, const World& world) {
    for (size_t i = 0; i < world.cut_plan.cuts.size(); ++i) {
        if (world.cut_plan.cuts[i].front_radius < 0.0) continue;
        try {
            scripted_cut_fronts(world, world.cut_plan.cuts[i].polygon);
        } catch (const std::invalid_argument& e) {
            throw InputError(scene.file, fmt::format("cuts[{}].front", i), e.what());
        }
    }
}

}  // namespace

void xcut_pipeline(const Scene& scene, Scheduler& scheduler, Simulation& sim) {
    World& world = sim.world;
    if (scene.visual_subdivisions >= 0) build_surface(world, world.visual, scene.visual_subdivisions);
    if (scene.collision_subdivisions >= 0) build_surface(world, world.collision, scene.collision_subdivisions);
    scheduler.add(tool_system([&sim](int i, double t) { return sim.devices[i]->pose(t); }));
    auto bvh = std::make_shared<ElementBvh>();
    const bool blades = (world.present() & kCutEvents) != 0;
    if (blades && world.tools.count() > 0) prepare_cut_search(world, *bvh);
    if (blades) prepare_enrichment(world);
    scheduler.add(cut_system(bvh));
    scheduler.add(scripted_cut_system());
    scheduler.add(world.snap.enabled ? snap_cut_system(world) : enrichment_system());
    if (world.tips.follow_radius >= 0.0) scheduler.add(crack_tip_system());
    if (has_scripted_fronts(world)) check_front_geometry(scene, world), scheduler.add(scripted_front_system());
    scheduler.add(pieces_system());
    scheduler.add(cutting_force_system(bvh));
    scheduler.add(force_system());
    scheduler.add(rebind_system());
    scheduler.add(collision_system(make_collision_model()));
    scheduler.add(grasp_system());
    const auto terms = std::make_shared<const StepOperator>(xcut_step_terms());
    prepare_linear_solver(world, *terms);  // before its system: the schedule line says what it chose
    scheduler.add(solver_system(world, terms));
    scheduler.add(watchdog_system());
    // The surface follows the tips' field (2D: slit up to the tip; 3D: no slit inside an element
    // the front runs through, docs/xfem.md), a 2D tip's element in the volume output too.
    if (world.tips.follow_radius >= 0.0 || has_scripted_fronts(world)) scheduler.add(crack_tip_display_system());
    scheduler.add(mapping_system());
    scheduler.add({"OutputSystem", kNodes | kElements | kOutput, 0, [&sim](World& w) {
                       if (sim.output) sim.output->frame_if_due(w);
                   }});
}

StepOperator xcut_step_terms() {
    return StepOperator{{elastic_step_term(), contact_step_term(), grasp_step_term(), crack_tip_step_term()}};
}

std::unique_ptr<Simulation> make_simulation(const Scene& scene, bool with_output, const std::string& replay_directory) {
    return build_simulation(scene, xcut_pipeline, with_output, replay_directory);
}

}  // namespace xcut
