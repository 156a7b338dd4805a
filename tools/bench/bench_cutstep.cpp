#include "tools/bench/bench_cutstep.h"

#include <algorithm>
#include <fmt/format.h>

#include "engine/error.h"
#include "engine/parallel.h"
#include "systems/kernels/solver/supernode_solve.h"
#include "systems/pipeline.h"
#include "systems/solver/linear_solver.h"
#include "tools/bench/bench.h"
#include "tools/bench/bench_cut.h"

namespace xcut {
namespace {

struct Case {
    std::string name;
    Scene scene;
    int steps;
};

/// The default skin, its cells `h` [m] (the scalpel's incision from 0.2 to 1.2 s; `steps` of 10 ms),
/// with the scene's `more` overrides.
Case skin(const std::string& name, double h, int steps, const std::vector<std::string>& more = {}) {
    std::vector<std::string> set = {fmt::format("mesh.element_size={}", h)};
    set.insert(set.end(), more.begin(), more.end());
    Scene s = load_scene("scenes/skin_slab.json", set);
    s.visual_subdivisions = s.collision_subdivisions = -1;
    return {name, s, steps};
}

/// The tissue block at about `tets` tetrahedra, a scalpel (edge 20 mm deep) drawn across its top
/// along x at 50 mm/s from the first step.
Case block(const std::string& name, int tets, int steps) {
    const std::string scalpel =
        "tools+={\"name\": \"scalpel\", \"blade\": {\"tip\": [0, 0, -0.02], \"heel\": [0, 0, 0.005]}, "
        "\"trajectory\": [{\"time\": 0, \"position\": [0, 0.0503, 0.05]}, {\"time\": 2, \"position\": [0.1, 0.0503, 0.05]}]}";
    return {name, sized_scene("scenes/tissue_block.json", tets, {scalpel}), steps};
}

std::vector<Case> cases(bool tiny) {
    if (tiny) return {skin("skin_2mm", 0.002, 40), block("block_5k", 5000, 30)};
    // The 0.7 mm skin renews its multigrid hierarchy during the cut, the 2 mm and 1 mm skins their
    // Cholesky factor (auto: the 1 mm skin's fill is a thin layer's): once more with it renewed in
    // the step (solver.renew_delay / factor_delay 0), for the off-step renewal's share in the same run.
    Case in_step_2mm = skin("skin_2mm_factor_in_step", 0.002, 130);
    in_step_2mm.scene.solver.factor_delay = 0;
    Case in_step_1mm = skin("skin_1mm_renew_in_step", 0.001, 130), in_step_07mm = skin("skin_0.7mm_renew_in_step", 0.0007, 130);
    for (Case* c : {&in_step_1mm, &in_step_07mm}) c->scene.solver.renew_delay = c->scene.solver.factor_delay = 0;
    // The crack front at the blade (cutter.tip): its zone built again at each stride the blade moves,
    // solved beside the factor in use, through the blade's stop at 1.2 s.
    const Case front_2mm = skin("skin_2mm_front", 0.002, 130, {"cutter.tip={}"});
    return {skin("skin_2mm", 0.002, 130), in_step_2mm, front_2mm, skin("skin_1mm", 0.001, 130), in_step_1mm,
            skin("skin_0.7mm", 0.0007, 130), in_step_07mm, block("block_20k", 20000, 100),
            block("block_53k", 53000, 100), block("block_200k", 200000, 60)};
}

double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

CutStepBenchRow run_case(const Case& c, const std::string& load) {
    CutStepBenchRow r;
    r.case_name = c.name, r.load = load;
    set_thread_count(2);
    r.own_peak = reset_peak_rss();
    auto sim = make_simulation(c.scene, false);
    World& w = sim->world;
    r.tets = w.mesh_elements;
    r.method = w.linear.method.empty() ? resolve_linear_method(w) : w.linear.method;
    std::vector<double> all, split, cg, cg_split;
    for (int i = 0; i < c.steps; ++i) {
        const int cut_before = w.cuts.count() + w.snap.elements_split;
        try {
            step_simulation(*sim);
        } catch (const NumericalError& e) {
            r.failure = e.what();
            break;
        }
        const StepMetrics& m = w.metrics.current;
        all.push_back(m.step_ms), cg.push_back(m.cg_iterations);
        r.builds += m.preconditioner == 3, r.swaps += m.preconditioner == 2;
        r.wait_max_ms = std::max(r.wait_max_ms, m.preconditioner_wait_ms);
        if (w.cuts.count() + w.snap.elements_split > cut_before) {
            split.push_back(m.step_ms), cg_split.push_back(m.cg_iterations);
            r.cut_to = i + 1;
            if (r.cut_from == 0) r.cut_from = i + 1;
        }
    }
    if (r.cut_from > 0) {
        const std::vector<double> cut(all.begin() + (r.cut_from - 1), all.begin() + r.cut_to);
        r.cut_p99_ms = percentile(cut, 0.99), r.cut_max_ms = max_of(cut);
    }
    r.steps = static_cast<int>(all.size()), r.split_steps = static_cast<int>(split.size());
    r.dofs_end = w.metrics.current.dofs;
    r.median_ms = percentile(all, 0.5), r.p99_ms = percentile(all, 0.99);
    r.max_ms = max_of(all);
    r.split_median_ms = percentile(split, 0.5);
    r.split_max_ms = max_of(split);
    r.cg_median = percentile(cg, 0.5), r.cg_split_median = percentile(cg_split, 0.5);
    r.cg_split_max = max_of(cg_split);
    r.peak_rss_mb = peak_rss_bytes() / 1e6;
    return r;
}

}  // namespace

std::vector<CutStepBenchRow> run_cutstep_bench(const CutStepBenchOptions& o) {
    std::vector<Case> all = cases(o.tiny);
    if (!o.cases.empty())
        std::erase_if(all, [&](const Case& c) { return std::find(o.cases.begin(), o.cases.end(), c.name) == o.cases.end(); });
    if (all.empty()) {
        const auto names = [](bool tiny) {
            std::string list;
            for (const Case& c : cases(tiny)) list += (list.empty() ? "" : ", ") + c.name;
            return list;
        };
        throw InputError("--cases", "", fmt::format("no such case in this configuration ({}; --tiny: {})", names(false), names(true)));
    }
    std::vector<CutStepBenchRow> rows;
    for (const Case& c : all) {
        rows.push_back(run_case(c, "quiet"));
        if (o.progress) fmt::print(stderr, "  {}: median {:.2f} ms, max {:.2f} ms\n", c.name, rows.back().median_ms, rows.back().max_ms);
    }
    // Beside a process that keeps one core busy (a renderer, a haptic thread): the default skin and
    // the 53k block (the first case of a --tiny run).
    const int busy = start_busy_process();
    for (const Case& c : all)
        if (c.name == "skin_2mm" || c.name == "block_53k" || (o.tiny && &c == &all.back())) rows.push_back(run_case(c, "busy"));
    stop_busy_process(busy);
    return rows;
}

int cutstep_bench_command(const CutStepBenchOptions& o) {
    const std::vector<CutStepBenchRow> rows = run_cutstep_bench(o);
    auto csv = open_csv(o.csv);
    csv.print("case,load,method,tets,steps,dofs_end,median_ms,p99_ms,max_ms,p99_over_median,max_over_median,split_steps,"
              "split_median_ms,split_max_ms,split_median_over_median,cg_median,cg_split_median,cg_split_max,builds,"
              "swaps,wait_max_ms,peak_rss_mb,peak_is_the_runs,cut_from_step,cut_to_step,cut_p99_ms,cut_max_ms,"
              "cut_p99_over_median,cut_max_over_median,failure\n");
    fmt::print("cut step benchmark: a scalpel cutting continuously; 2 threads, no output; every step timed; the factor's "
               "solves on the {} kernels\n", supernode_kernels<double>().name);
    fmt::print("{:>11} {:>5} {:>8} {:>7} {:>6} {:>9} {:>9} {:>9} {:>7} {:>7} {:>8} {:>6} {:>10} {:>9} {:>8} {:>7}\n",
               "case", "load", "method", "tets", "steps", "median", "p99", "max", "p99/med", "max/med", "cut p99/max",
               "splits", "split med", "split max", "cg split", "built/swap");
    for (const CutStepBenchRow& r : rows) {
        const double med = r.median_ms > 0 ? r.median_ms : 1.0;
        fmt::print("{:>11} {:>5} {:>8} {:>7} {:>6} {:>7.2f}ms {:>7.2f}ms {:>7.2f}ms {:>7.1f} {:>7.1f} {:>5.1f}/{:<5.1f} {:>6} "
                   "{:>8.2f}ms {:>7.2f}ms {:>4.0f}/{:<3.0f} {:>4}/{:<4}{}\n",
                   r.case_name, r.load, r.method, r.tets, r.steps, r.median_ms, r.p99_ms, r.max_ms, r.p99_ms / med,
                   r.max_ms / med, r.cut_p99_ms / med, r.cut_max_ms / med, r.split_steps, r.split_median_ms, r.split_max_ms, r.cg_split_median, r.cg_split_max,
                   r.builds, r.swaps, r.failure.empty() ? "" : "  FAILED: " + r.failure);
        csv.print("{},{},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.3f},{:.3f},{},{:.4f},{:.4f},{:.3f},{},{},{},{},{},{:.3f},{:.1f},{},"
                  "{},{},{:.4f},{:.4f},{:.3f},{:.3f},\"{}\"\n",
                  r.case_name, r.load, r.method, r.tets, r.steps, r.dofs_end, r.median_ms, r.p99_ms, r.max_ms,
                  r.p99_ms / med, r.max_ms / med, r.split_steps, r.split_median_ms, r.split_max_ms,
                  r.split_median_ms / med, r.cg_median, r.cg_split_median, r.cg_split_max, r.builds, r.swaps,
                  r.wait_max_ms, r.peak_rss_mb, r.own_peak ? 1 : 0, r.cut_from, r.cut_to, r.cut_p99_ms, r.cut_max_ms,
                  r.cut_p99_ms / med, r.cut_max_ms / med, r.failure);
    }
    fmt::print("targets (issue #36): p99 <= 1.5x and max <= 2x the median step at every size, also beside a busy "
               "process (cut p99/max: over the steps from the first split to the last, against the same median)\ncsv: {}\n",
               o.csv);
    return 0;
}

}  // namespace xcut
