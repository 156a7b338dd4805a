// What a system declares is what it touches: the shipped scenes that exercise every system (tools
// with contact, the XFEM and the snapping cutter, scripted cuts) step with the scheduler's access
// check on (engine/access_check.h), which hashes every component before and after each system; an
// undeclared write would stop the step. The generated dataflow in docs/architecture.md is thereby
// true.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "engine/access_check.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

/// Steps the scene with the check on; returns the world's figures the caller expects to have moved
/// (elements split by either cutter, the most contacts in a step), so the run is known to have
/// exercised what it was chosen for.
std::pair<int, int> step_checked(const std::string& scene_name, const std::vector<std::string>& overrides, int steps) {
    SCOPED_TRACE(scene_name);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/" + scene_name + ".json", overrides);
    auto sim = make_simulation(scene, /*with_output=*/false);
    sim->scheduler.set_access_check(true);
    int contacts = 0;
    for (int i = 0; i < steps; ++i) {
        EXPECT_NO_THROW(step_simulation(*sim)) << "step " << i;
        contacts = std::max(contacts, sim->world.contacts.count());
    }
    return {sim->world.cuts.count() + sim->world.snap.elements_split, contacts};
}

TEST(AccessCheck, EverySystemWritesOnlyWhatItDeclares) {
    // Incision, then the retractor and the probe press (from t = 1.9 s; dt doubled to get there sooner).
    const auto surgery = step_checked("open_surgery", {"solver.dt=0.02"}, 110);
    EXPECT_GT(surgery.first, 0);
    EXPECT_GT(surgery.second, 0);
    EXPECT_GT(step_checked("skin_slab", {}, 40).first, 0);                                   // the scalpel's incision
    EXPECT_GT(step_checked("skin_slab", {"cutter.type=\"snap\""}, 40).first, 0);             // the snapping baseline
    EXPECT_GT(step_checked("skin_slab", {"cutter.front=\"progressive\""}, 40).first, 0);     // the progressive front
    EXPECT_GT(step_checked("slab_planar_cut", {}, 40).first, 0);                              // a scripted cut
}

// The check itself: a system that moves the nodes while declaring no write is stopped, named.
TEST(AccessCheck, AnUndeclaredWriteIsNamed) {
    World w;
    w.nodes.position.assign(2, Vec3::Zero());
    w.nodes.rest = w.nodes.velocity = w.nodes.position;
    w.nodes.mass.assign(2, 1.0);
    w.nodes.fixed.assign(2, 0);
    Scheduler s;
    s.add({"Sneaky", kNodes, 0, [](World& world) { world.nodes.position[1].x() += 1.0; }});
    s.add({"Honest", kNodes, kNodes, [](World& world) { world.nodes.position[0].x() += 1.0; }});
    s.build(w);
    s.set_access_check(true);
    try {
        s.step(w);
        ADD_FAILURE() << "an undeclared write went through";
    } catch (const std::logic_error& e) {
        EXPECT_NE(std::string(e.what()).find("Sneaky wrote Nodes without declaring it"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace xcut
