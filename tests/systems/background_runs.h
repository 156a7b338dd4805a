#pragma once
// The default skin run through its incision with a preconditioner renewed off the step (the amg
// hierarchy, the Cholesky factor), and the checks both share: the same bits for any thread count
// and beside a busy core, and positions close to renewing in the step.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <functional>
#include <thread>

#include "engine/parallel.h"
#include "systems/pipeline.h"

namespace xcut {

struct SkinRun {
    std::vector<Vec3> position;
    std::vector<int> state, iterations;  ///< per step: metrics' preconditioner, CG iterations
    std::vector<double> residual;        ///< per step
    int cuts = 0, augmented = 0, swaps = 0;
};

/// `steps` steps of the default skin on `threads` threads with the scene's solver settings as
/// `set` leaves them (and the scene's `overrides`, as `xcut run --set` takes them).
inline SkinRun run_default_skin(int threads, int steps, const std::function<void(SolverSettings&)>& set,
                                const std::vector<std::string>& overrides = {}) {
    set_thread_count(threads);
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json", overrides);
    scene.visual_subdivisions = scene.collision_subdivisions = -1;
    set(scene.solver);
    auto sim = make_simulation(scene, false);
    SkinRun r;
    for (int i = 0; i < steps; ++i) {
        step_simulation(*sim);
        const StepMetrics& m = sim->world.metrics.current;
        r.state.push_back(m.preconditioner), r.iterations.push_back(m.cg_iterations), r.residual.push_back(m.cg_residual);
    }
    r.position = sim->world.nodes.position;
    r.cuts = sim->world.cuts.count();
    r.augmented = sim->world.linear.augmented_steps, r.swaps = sim->world.linear.swaps;
    set_thread_count(2);
    return r;
}

/// run(threads) gives the same bits on 1 and 2 threads, and on 2 beside a core kept busy (the
/// background work then finishes later).
inline void expect_same_bits_for_any_thread_count_and_load(const std::function<SkinRun(int)>& run) {
    const SkinRun one = run(1), two = run(2);
    std::atomic<bool> stop{false};
    std::thread busy([&] {
        volatile double x = 0.0;
        while (!stop) x = x * 0.999 + 1.0;
    });
    const SkinRun loaded = run(2);
    stop = true;
    busy.join();
    ASSERT_EQ(one.position.size(), two.position.size());
    for (size_t i = 0; i < one.position.size(); ++i) {
        ASSERT_EQ(one.position[i], two.position[i]) << "node " << i;
        ASSERT_EQ(two.position[i], loaded.position[i]) << "node " << i;
    }
    EXPECT_EQ(one.state, loaded.state);
}

/// Renewed off the step (`off`) against in it (`in`): the same cut, positions within the CG
/// tolerance's effect (both solves stop at a relative residual of 1e-6).
inline void expect_close_to_renewing_in_the_step(const SkinRun& off, const SkinRun& in) {
    for (int s : in.state) EXPECT_NE(s, 2) << "renewed in the step: nothing taken from off it";
    double max_u = 0.0, max_diff = 0.0;
    for (size_t i = 0; i < in.position.size(); ++i) max_diff = std::max(max_diff, (off.position[i] - in.position[i]).norm());
    for (const Vec3& p : in.position) max_u = std::max(max_u, std::abs(p.z()));  // the sag [m]
    EXPECT_EQ(off.cuts, in.cuts);
    std::printf("  renewed off the step against in it: positions differ by at most %.3g m (sag %.3g m)\n", max_diff, max_u);
    EXPECT_LT(max_diff, 1e-6 * std::max(max_u, 1e-3)) << "largest difference " << max_diff << " m";
}

}  // namespace xcut
