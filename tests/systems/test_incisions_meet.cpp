// Two incisions that meet: a node's copies are the classes of material connectivity around it
// (systems/cut/node_copies.cpp), so a second incision reaching the first wound from one of its sides
// gets copies of its own there, not the wound's far-lip phantom. A split never changes the elastic
// energy: a new virtual element starts with its parent's shape.
#include <gtest/gtest.h>

#include "systems/force_system.h"
#include "systems/pipeline.h"
#include "systems/xfem_queries.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

/// The 60 x 40 x 2 mm skin patch stretched 1 mm at each end in x, cut at t = 0.01 s by the plane
/// x = 31 mm over y 10-30 mm, through its thickness: the wound opens in x.
std::unique_ptr<Simulation> opened_wound() {
    const std::string text = R"({
      "mesh": {"generator": "box", "origin": [0, 0, 0], "size": [0.06, 0.04, 0.002], "element_size": 0.002},
      "material": {"young": 1e4, "poisson": 0.3, "density": 1000},
      "constraints": {"fixed_boxes": [
        {"min": [-1e-6, -1, -1], "max": [1e-6, 1, 1], "displacement": [-0.001, 0, 0]},
        {"min": [0.059999, -1, -1], "max": [0.060001, 1, 1], "displacement": [0.001, 0, 0]}]},
      "cuts": [{"time": 0.01, "polygon": [[0.031, 0.01, -1], [0.031, 0.03, -1], [0.031, 0.03, 1], [0.031, 0.01, 1]]}],
      "solver": {"dt": 0.01, "damping": {"mass": 2.0, "stiffness": 0.01}},
      "steps": 40
    })";
    return make_simulation(load_scene_text(text, "opened wound", "."), /*with_output=*/false);
}

double total_energy(const World& w) { return elastic_energy_now(w) + w.metrics.current.kinetic_energy; }

TEST(IncisionsMeet, AStemFromAnOpenWoundStartsWithoutAJumpInEnergy) {
    auto sim = opened_wound();
    for (int i = 0; i < 20; ++i) step_simulation(*sim);
    World& w = sim->world;
    double opening = 0.0;
    for (int j = 0; j < w.mesh_nodes; ++j) opening = std::max(opening, enriched_displacement(w, j).norm());
    ASSERT_GT(opening, 1e-4) << "the first wound is open";
    // The T's stem: the plane y = 20.5 mm from the wound (x = 31 mm) to x = 50 mm. Its elements at
    // x = 32-34 mm share the nodes at x = 32 mm with the wound's elements, whose phantoms moved with
    // the wound's far lip.
    const double before = elastic_energy_now(w);
    queue_polygon_cut(w, {Vec3(0.031, 0.0205, -1), Vec3(0.05, 0.0205, -1), Vec3(0.05, 0.0205, 1), Vec3(0.031, 0.0205, 1)});
    ASSERT_GT(apply_cut_events(w), 0);
    EXPECT_NEAR(elastic_energy_now(w), before, 1e-9 * before);
    // Nothing works on the patch from now on (its ends stay where they are): backward Euler only
    // dissipates.
    const double start = total_energy(w);
    for (int i = 0; i < 20; ++i) {
        step_simulation(*sim);
        ASSERT_LE(total_energy(w), start * (1.0 + 1e-9)) << "step " << i;
    }
}

TEST(IncisionsMeet, ACutContinuingAWoundOpensAtItsOldFront) {
    // The same wound lengthened along its own plane (to y = 36 mm): its new elements use the phantoms
    // of the nodes at the old front (held shut until now), so the wound opens there and beyond.
    auto sim = opened_wound();
    for (int i = 0; i < 20; ++i) step_simulation(*sim);
    World& w = sim->world;
    const auto opening_at = [&w](double y) {
        double most = 0.0;
        for (int j = 0; j < w.mesh_nodes; ++j)
            if (std::abs(w.nodes.rest[j].y() - y) < 1e-9) most = std::max(most, enriched_displacement(w, j).norm());
        return most;
    };
    EXPECT_LT(opening_at(0.030), 1e-12) << "the old front is held shut";
    queue_polygon_cut(w, {Vec3(0.031, 0.029, -1), Vec3(0.031, 0.036, -1), Vec3(0.031, 0.036, 1), Vec3(0.031, 0.029, 1)});
    ASSERT_GT(apply_cut_events(w), 0);
    for (int i = 0; i < 10; ++i) step_simulation(*sim);
    EXPECT_GT(opening_at(0.030), 1e-4);
    EXPECT_GT(opening_at(0.034), 1e-4);
}

}  // namespace
}  // namespace xcut
