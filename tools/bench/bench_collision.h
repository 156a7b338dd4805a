#pragma once
// Collision benchmark (`xcut bench --suite collision`): the CollisionSystem's time per step against
// the collision surface's size and the number of tools pressing it, and the haptic loop's rate and
// jitter while the physics runs on the other core.
#include <string>
#include <vector>

namespace xcut {

struct CollisionBenchOptions {
    std::vector<int> subdivisions{0, 1, 2, 3};  ///< collision surface levels over a 6k-tet block
    std::vector<int> tools{1, 2, 4};            ///< probes pressing the block
    int steps = 30;                             ///< timed steps per row
    int haptic_steps = 200;                     ///< physics steps run beside the haptic loop
    std::string csv = "results/bench_collision.csv";
};

int collision_bench_command(const CollisionBenchOptions& options);

}  // namespace xcut
