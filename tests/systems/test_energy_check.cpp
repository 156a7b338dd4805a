// The energy check of the once-linearized step (systems/solver/energy_check.h): a step that gains
// energy goes on with Newton iterations; a run none of whose steps gains is the same to the bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/fnv_hash.h"
#include "systems/force_system.h"
#include "engine/io/scene.h"
#include "engine/simulation.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

std::string scene_path(const char* name) { return std::string(XCUT_SOURCE_DIR) + "/scenes/" + name; }

/// Kinetic + strain + gravity's potential energy of the world now [J] (the rotations taken from the
/// positions), an independent reading of the balance the check keeps.
double total_energy(const World& w) {
    double gravity = 0.0, kinetic = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) {
        gravity -= w.nodes.mass[i] * w.gravity.dot(w.nodes.position[i]);
        kinetic += 0.5 * w.nodes.mass[i] * w.nodes.velocity[i].squaredNorm();
    }
    return kinetic + elastic_energy_now(w) + gravity;
}

struct FlapRun {
    double most_gained = 0.0;  ///< the largest rise of the total energy over its start [J]
    double gravity_drop = 0.0; ///< the gravity potential's largest fall from the start [J]
    int checked_newton = 0;    ///< steps the check iterated
};

/// The flap of scenes/flap_lift.json sagging from rest under its own weight (0.2 s, before the probe
/// comes: no tool acts), its energy read after each step.
/// `on_energy_gain` empty: the scene's default.
FlapRun sag_flap(const std::string& on_energy_gain) {
    std::vector<std::string> overrides{"duration=0.2", "output.vtu=false", "output.metrics_csv=false"};
    if (!on_energy_gain.empty()) overrides.push_back("solver.newton.on_energy_gain=" + on_energy_gain);
    Scene scene = load_scene(scene_path("flap_lift.json"), overrides);
    auto sim = make_simulation(scene, /*with_output=*/false);
    World& w = sim->world;
    const double start = total_energy(w);
    double gravity0 = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) gravity0 -= w.nodes.mass[i] * w.gravity.dot(w.nodes.position[i]);
    FlapRun r;
    for (int n = 0; n < scene.steps; ++n) {
        step_simulation(*sim);
        double gravity = 0.0;
        for (int i = 0; i < w.nodes.count(); ++i) gravity -= w.nodes.mass[i] * w.gravity.dot(w.nodes.position[i]);
        r.gravity_drop = std::max(r.gravity_drop, gravity0 - gravity);
        r.most_gained = std::max(r.most_gained, total_energy(w) - start);
    }
    r.checked_newton = w.metrics.energy_newton_steps;
    return r;
}

// The quadratic flap (nu 0.48, dt 10 ms) released from rest: the once-linearized step alone gains
// several times the work gravity does in its first steps (its strain energy overshoots); with the
// check, the steps that gain are iterated and the total energy stays at its start within 1 % of
// gravity's work (backward Euler dissipates).
TEST(EnergyCheck, AFlapSaggingFromRestGainsOnceLinearizedAndNotWithTheCheck) {
    const FlapRun alone = sag_flap("0"), checked = sag_flap("");
    std::printf("  measured: gained %.3g J once linearized alone, %.3g J checked (%d steps iterated); gravity's work %.3g J\n",
                alone.most_gained, checked.most_gained, checked.checked_newton, checked.gravity_drop);
    EXPECT_EQ(alone.checked_newton, 0);
    EXPECT_GT(alone.most_gained, 2.0 * alone.gravity_drop) << "the once-linearized step's gain";
    EXPECT_GT(checked.checked_newton, 0);
    EXPECT_LE(checked.most_gained, 0.01 * checked.gravity_drop)
        << "gained " << checked.most_gained << " J against gravity's " << checked.gravity_drop << " J";
}

uint64_t skin_hash(const std::string& on_energy_gain, int& checked_newton) {
    std::vector<std::string> overrides{"output.vtu=false", "output.metrics_csv=false"};
    if (!on_energy_gain.empty()) overrides.push_back("solver.newton.on_energy_gain=" + on_energy_gain);
    Scene scene = load_scene(scene_path("skin_slab.json"), overrides);
    auto sim = make_simulation(scene, /*with_output=*/false);
    Hasher h;
    for (int n = 0; n < scene.steps; ++n) {
        step_simulation(*sim);
        h.add(sim->world.metrics.current.cg_iterations);
        h.bytes(sim->world.nodes.position.data(), sim->world.nodes.position.size() * sizeof(Vec3));
    }
    checked_newton = sim->world.metrics.energy_newton_steps;
    return h.h;
}

// The default skin's incision gains in no step, so the check changes no bit: the rotations it takes
// at the step's end positions are the ones the next step takes (update_rotations reuses them where
// an element's deformation gradient is the same to the bit, and computes the rest).
TEST(EnergyCheck, ARunNoneOfWhoseStepsGainsIsTheSameToTheBit) {
    int with = -1, without = -1;
    const uint64_t checked = skin_hash("", with), alone = skin_hash("0", without);
    EXPECT_EQ(with, 0);
    EXPECT_EQ(without, 0);
    EXPECT_EQ(checked, alone);
}

// The probe of scenes/open_surgery.json parts the wound and presses the tissue: its contacts' work on
// the tissue is counted exactly (the held terms are linear within the step), so no step is taken for
// a gain. Bounded as the watchdog bounds the tools' work (|F . v| dt), 30 of its steps were.
TEST(EnergyCheck, AProbeInContactDoesItsWorkAndNoStepGains) {
    Scene scene = load_scene(scene_path("open_surgery.json"), {"output.vtu=false", "output.metrics_csv=false"});
    auto sim = make_simulation(scene, /*with_output=*/false);
    int contact_steps = 0;
    for (int n = 0; n < scene.steps; ++n) {
        step_simulation(*sim);
        contact_steps += sim->world.contacts.count() > 0;
    }
    EXPECT_GT(contact_steps, 20);
    EXPECT_EQ(sim->world.metrics.energy_newton_steps, 0);
}

}  // namespace
}  // namespace xcut
