// docs/verification.md problem 10: the same scene and thread count give bit-identical positions after N
// steps, and so do 1 and 2 threads (tolerance: none, every bit). The reductions are summed in fixed
// blocks and forces gathered per node in element order, so no result depends on the thread count.
#include <gtest/gtest.h>


#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::state_hash;

/// The default scene (a scalpel incision in the skin patch), large enough that every parallel loop
/// really splits (3600 tets > the 2048-item serial cut-off), run for 30 steps.
uint64_t run_default_scene(int threads, const std::string& front = "semi") {
    set_thread_count(threads);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
    scene.cut_front = front;
    scene.solver.dt = 0.03;             // the blade cuts within the run
    scene.solver.cg_tolerance = 1e-4;   // fewer iterations: the test is about bits, not accuracy
    auto sim = make_simulation(scene, /*with_output=*/false);
    for (int i = 0; i < 30; ++i) step_simulation(*sim);
    EXPECT_GT(sim->world.cuts.count(), 0) << "the run cuts";
    set_thread_count(2);
    return state_hash(sim->world);
}

TEST(Determinism, SameThreadCountIsBitIdentical) { EXPECT_EQ(run_default_scene(2), run_default_scene(2)); }

TEST(Determinism, OneAndTwoThreadsAreBitIdentical) { EXPECT_EQ(run_default_scene(1), run_default_scene(2)); }

// The progressive front (tip elements split on entry, crossings queued as events) keeps both.
TEST(Determinism, ProgressiveFrontIsBitIdentical) {
    const uint64_t two = run_default_scene(2, "progressive");
    EXPECT_EQ(two, run_default_scene(2, "progressive"));
    EXPECT_EQ(two, run_default_scene(1, "progressive"));
    EXPECT_NE(two, run_default_scene(2)) << "the front changes the run";
}

TEST(RealTimeMode, TimeStepFollowsMeasuredStepTimeWithinBounds) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/tissue_block.json");
    scene.solver.realtime = true;
    scene.solver.dt_min = 1e-4;
    scene.solver.dt_max = 2e-2;
    auto sim = make_simulation(scene, false);
    for (int i = 0; i < 5; ++i) {
        step_simulation(*sim);
        const StepMetrics& m = sim->world.metrics.current;
        const double expected = std::clamp(m.step_ms * 1e-3, 1e-4, 2e-2);
        EXPECT_EQ(sim->world.solver.dt, expected) << "the next dt is the measured step time, clamped";
    }
}

}  // namespace
}  // namespace xcut
