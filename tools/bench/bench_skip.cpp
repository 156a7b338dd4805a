#include "tools/bench/bench_skip.h"

#include <algorithm>
#include <fmt/format.h>

#include "engine/io/output.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

/// A scalpel drawn along x across the top of the 100 x 100 x 50 mm block at 50 mm/s, its blade
/// 20 mm deep, a capsule handle above the surface; a visual surface (1 subdivision) and a
/// collision surface (the boundary).
const std::vector<std::string> kWithTools = {
    R"(tools=[{"name": "scalpel", "blade": {"tip": [0, 0, -0.02], "heel": [0, 0, 0.005]},
              "shape": {"type": "capsule", "radius": 0.004, "length": 0.06, "centre": [0, 0, 0.04]},
              "trajectory": [{"time": 0, "position": [0.0, 0.0503, 0.05]},
                             {"time": 2, "position": [0.1, 0.0503, 0.05]}]}])",
    R"(visual={"subdivisions": 1})",
    R"(collision={"subdivisions": 0})",
};

void time_scene(const Scene& scene, const std::string& label, int steps, std::vector<SkipBenchRow>& out) {
    auto sim = make_simulation(scene, false);
    const World& w = sim->world;
    for (int i = 0; i < 2; ++i) step_simulation(*sim);
    const auto& names = w.metrics.system_names;
    std::vector<double> ms(names.size(), 0.0);
    std::vector<int> calls(names.size(), 0);
    double step_ms = 0.0;
    for (int i = 0; i < steps; ++i) {
        step_simulation(*sim);
        const StepMetrics& m = w.metrics.current;
        for (size_t s = 0; s < m.system_ms.size(); ++s) ms[s] += m.system_ms[s] / steps, ++calls[s];
        step_ms += m.step_ms / steps;
    }
    for (const SystemDesc& d : sim->scheduler.registered()) {
        SkipBenchRow r;
        r.scene = label;
        r.system = d.name;
        r.step_ms = step_ms;
        const auto it = std::find(names.begin(), names.end(), d.name);
        if (it != names.end()) {
            const size_t s = it - names.begin();
            r.scheduled = true;
            r.calls = calls[s];
            r.ms_per_step = ms[s];
        }
        out.push_back(r);
    }
}

}  // namespace

std::vector<SkipBenchRow> run_skip_bench(const std::string& scene, int tets, int steps) {
    std::vector<SkipBenchRow> rows;
    ProgressBar bar("skip", 2);
    time_scene(sized_scene(scene, tets, kWithTools), "with", steps, rows);
    bar.update(1);
    time_scene(sized_scene(scene, tets), "without", steps, rows);
    bar.update(2);
    bar.finish();
    return rows;
}

void skip_row(const PerfBenchOptions& o) {
    const auto rows = run_skip_bench(o.scene, o.skip_tets, o.steps);
    auto csv = open_csv(sibling_csv(o.csv, "skip"));
    csv.print("scene,system,scheduled,calls,ms_per_step,step_ms\n");
    fmt::print("\nskip what the scene doesn't need: {} at {} tets with a scalpel, visual and collision surfaces, "
               "and without ({} threads)\n",
               o.scene, o.skip_tets, configured_thread_count());
    fmt::print("{:>8} {:<18} {:>9} {:>6} {:>10}\n", "scene", "system", "scheduled", "calls", "ms/step");
    for (const SkipBenchRow& r : rows) {
        fmt::print("{:>8} {:<18} {:>9} {:>6} {:>10.4f}\n", r.scene, r.system, r.scheduled ? "yes" : "skipped", r.calls,
                   r.ms_per_step);
        csv.print("{},{},{},{},{:.5f},{:.5f}\n", r.scene, r.system, r.scheduled ? 1 : 0, r.calls, r.ms_per_step, r.step_ms);
    }
    for (const char* scene : {"with", "without"}) {
        double step = 0.0, systems = 0.0;
        for (const SkipBenchRow& r : rows)
            if (r.scene == scene) step = r.step_ms, systems += r.ms_per_step;
        fmt::print("{:>8}: step {:.3f} ms, of which the scheduled systems {:.3f} ms (scheduler {:.4f} ms)\n", scene, step,
                   systems, step - systems);
    }
}

}  // namespace xcut
