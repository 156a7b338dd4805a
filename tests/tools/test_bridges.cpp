// The stress suite's "no bridge" check (tools/studies/bridges.h) and the cut it checks, on the stress
// suite's slab (40 x 40 x 4 mm held at its x borders, sagging under gravity) cut by a scalpel
// reaching below it: a straight incision leaves no element it crossed through joined, and the same
// sweep over the slab left uncut finds every one of them bridged.
#include <gtest/gtest.h>

#include <random>

#include "systems/pipeline.h"
#include "tools/studies/bridges.h"
#include "tools/studies/stress.h"

namespace xcut {
namespace {

struct Tallies {
    BridgeTally cut;    ///< the world as the run cut it
    BridgeTally uncut;  ///< the same sweep over the slab never cut
};

/// The stress slab cut by an upright scalpel through the slab (tip 2 mm below it) along `points`
/// (x, y [m], 0.2 s apart), kRandomCutSteps steps.
Tallies incision(const std::vector<std::array<double, 2>>& points) {
    std::mt19937_64 rng(1);
    Scene s = random_cut_scene(rng);
    ToolBodies& tb = s.tools;
    tb.blade_tip = {Vec3(0, 0, -0.006)};
    tb.blade_heel = {Vec3(0, 0, 0.003)};
    std::vector<Keyframe> keys(points.size());
    for (size_t k = 0; k < points.size(); ++k) {
        keys[k].time = 0.2 * static_cast<double>(k);
        keys[k].position = Vec3(points[k][0], points[k][1], 0.004);
    }
    tb.trajectory = {keys};
    tb.position = {keys.front().position};
    tb.orientation = {keys.front().orientation};
    auto sim = make_simulation(s, false);
    BridgeCheck check;
    for (int n = 0; n < kRandomCutSteps; ++n) {
        check.before_step(sim->world);
        step_simulation(*sim);
    }
    auto never_cut = make_simulation(s, false);
    return {check.tally(sim->world), check.tally(never_cut->world)};
}

TEST(Bridges, AStraightIncisionLeavesNoElementItCrossedThroughJoined) {
    const Tallies t = incision({{{0.005, 0.0213}}, {{0.020, 0.0213}}, {{0.035, 0.0213}}});
    EXPECT_GT(t.cut.crossed, 20) << "the incision crosses elements through the slab's thickness";
    EXPECT_EQ(t.cut.bridged, 0);
    EXPECT_EQ(t.cut.left_out, 0) << "no face, no element inverted";
    EXPECT_EQ(t.uncut.crossed, t.cut.crossed);
    EXPECT_EQ(t.uncut.bridged, t.uncut.crossed) << "left uncut, every element crossed through is a bridge";
}

// A V incision, the blade turning 67 degrees at its apex: its sweep is sampled and cut at the turn
// (cuts_at_turns), so no quad cuts the chord across the apex and leaves the elements there whole
// (with the quads from the threshold alone, 12 of its 85 elements crossed through stay joined).
TEST(Bridges, AVIncisionLeavesNoElementAtItsApexJoined) {
    const Tallies t = incision({{{0.005, 0.0113}}, {{0.020, 0.0213}}, {{0.035, 0.0113}}});
    EXPECT_GT(t.cut.crossed, 40);
    EXPECT_EQ(t.cut.bridged, 0);
    EXPECT_EQ(t.uncut.bridged, t.uncut.crossed);
}

}  // namespace
}  // namespace xcut
