// The amg method's hierarchy renewed off the step (systems/solver/amg_background.h): taken at a
// fixed step after it was asked for, the same bits at any thread count and under any load, every
// step at the scene's tolerance, and close to renewing in the step.
#include "tests/systems/background_runs.h"

namespace xcut {
namespace {

/// The default skin with amg, its hierarchy aged every 5 solves, through its incision (60 steps).
SkinRun run_skin(int threads, int renew_delay) {
    return run_default_skin(threads, 60, [&](SolverSettings& s) {
        s.linear = "amg";
        s.refactor_every = 5;
        s.renew_delay = renew_delay;
    });
}

TEST(AmgBackground, RenewedOffTheStepAndTakenAtAFixedStep) {
    const SkinRun r = run_skin(2, 3);
    ASSERT_GT(r.cuts, 0) << "the blade cut during the run";
    int swaps = 0, built = 0;
    for (size_t i = 0; i < r.state.size(); ++i) {
        EXPECT_LE(r.residual[i], 1e-6) << "step " << i + 1;
        swaps += r.state[i] == 2, built += r.state[i] == 3;
        // An aged hierarchy: asked for at a step marked 1, in use three steps, taken at the fourth.
        if (r.state[i] == 1 && (i == 0 || r.state[i - 1] != 1)) {
            ASSERT_LT(i + 3, r.state.size());
            EXPECT_EQ(r.state[i + 1], 1);
            EXPECT_EQ(r.state[i + 2], 1);
            EXPECT_EQ(r.state[i + 3], 2) << "taken at the fixed step after asking, step " << i + 4;
        }
    }
    EXPECT_GE(swaps, 5);
    EXPECT_EQ(built, 0) << "no step built a hierarchy itself (the cut is carried over)";
}

TEST(AmgBackground, SameBitsForAnyThreadCountAndLoad) {
    expect_same_bits_for_any_thread_count_and_load([](int threads) { return run_skin(threads, 3); });
}

TEST(AmgBackground, CloseToRenewingInTheStep) { expect_close_to_renewing_in_the_step(run_skin(2, 3), run_skin(2, 0)); }

}  // namespace
}  // namespace xcut
