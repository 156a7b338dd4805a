#pragma once
// Mapping benchmark (`xcut bench --suite mapping`): per-step time to place the visual surface's
// vertices against their count (1 and 2 threads), and the time to re-bind and subdivide the surface
// per split element while a scalpel cuts.
#include <string>
#include <vector>

namespace xcut {

struct MappingBenchOptions {
    std::vector<int> subdivisions{1, 2, 3, 4};   ///< visual levels over a 20k-tet block
    std::vector<int> threads{1, 2};
    int repeats = 50;                            ///< position updates timed per row
    std::string csv = "results/bench_mapping.csv";
};

int mapping_bench_command(const MappingBenchOptions& options);

}  // namespace xcut
