#include "tools/bench/bench_mapping.h"

#include <chrono>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>

#include "tools/bench/bench_cut.h"
#include "engine/parallel.h"
#include "systems/cut/cut_system.h"
#include "systems/cut/enrichment_system.h"
#include "systems/surface/mapping_system.h"
#include "systems/tool_system.h"

namespace xcut {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

int mapping_bench_command(const MappingBenchOptions& o) {
    const std::filesystem::path path(o.csv);
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    auto csv = fmt::output_file(o.csv);
    csv.print("subdivisions,vertices,triangles,threads,update_ms,ns_per_vertex,rebind_us_per_split\n");
    fmt::print("mapping benchmark: 20k-tet block; vertex update per step, and re-bind + surface cut per split element\n");
    fmt::print("{:>5} {:>9} {:>9} {:>7} {:>10} {:>10} {:>16}\n", "subdv", "vertices", "triangles", "threads",
               "update ms", "ns/vertex", "rebind us/split");
    for (int sub : o.subdivisions) {
        // Re-binding and cutting the surface along a full incision (single-threaded work).
        World w = block_with_scalpel(20000, 0.05);
        build_visual_surface(w, sub);
        const int vertices = w.visual.vertex_count();
        const size_t triangles = w.visual.triangles.size();
        ElementBvh bvh;
        prepare_cut_search(w, bvh);
        prepare_enrichment(w);
        double rebind_ms = 0.0;
        int splits = 0;
        for (double t = 0.0; t <= 2.01; t += 0.01) {
            w.time = t;
            advance_tools(w, t);
            run_cut_system(w, bvh);
            splits += apply_cut_events(w);
            const auto t0 = Clock::now();
            rebind_cut_vertices(w);
            rebind_ms += ms_since(t0);
        }
        for (int threads : o.threads) {
            set_thread_count(threads);
            update_surface_positions(w);
            const auto t0 = Clock::now();
            for (int r = 0; r < o.repeats; ++r) update_surface_positions(w);
            const double ms = ms_since(t0) / o.repeats;
            const double per_split = splits > 0 ? 1e3 * rebind_ms / splits : 0.0;
            fmt::print("{:>5} {:>9} {:>9} {:>7} {:>10.3f} {:>10.1f} {:>16.1f}\n", sub, vertices, triangles, threads, ms,
                       1e6 * ms / vertices, per_split);
            csv.print("{},{},{},{},{:.5f},{:.3f},{:.3f}\n", sub, vertices, triangles, threads, ms, 1e6 * ms / vertices,
                      per_split);
        }
    }
    set_thread_count(2);
    return 0;
}

}  // namespace xcut
