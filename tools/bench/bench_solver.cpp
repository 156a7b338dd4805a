#include "tools/bench/bench_solver.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fmt/format.h>

#include "engine/error.h"
#include "engine/io/output.h"
#include "engine/parallel.h"
#include "systems/kernels/solver/supernode_solve.h"
#include "systems/pipeline.h"
#include "tools/bench/bench.h"

namespace xcut {
namespace {

/// A method name, or "<method> guess 0": the method with solver.guess_history = 0.
constexpr const char* kNoGuess = " guess 0";

struct Case {
    std::string name;
    Scene scene;
    int steps;
    std::vector<std::string> methods;
};

/// A thin, curved, sliver-rich membrane: 80 x 60 x 1 mm bent around a 30 mm radius, 2 mm cells
/// jittered by 0.3 of a cell, held along its two short edges, under gravity.
Scene thin_membrane(bool tiny) {
    Scene s = sized_scene("scenes/tissue_block.json", 1000);
    s.name = "thin_membrane";
    s.mesh.grid.size = Vec3(0.08, 0.06, 0.001);
    s.mesh.grid.cells = tiny ? Eigen::Vector3i(20, 15, 1) : Eigen::Vector3i(40, 30, 1);
    s.mesh.grid.jitter = 0.3;
    s.mesh.grid.bend_radius = 0.03;
    s.constraints.boxes.clear();
    s.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7, Vec3::Zero()});
    s.constraints.boxes.push_back({Vec3(0.08 - 1e-9, -1, -1), Vec3(1, 1, 1), 7, Vec3::Zero()});
    return s;
}

std::vector<Case> cases(bool tiny) {
    const std::vector<std::string> all = {"jacobi", "block_jacobi", "amg", "cholesky", "direct"};
    std::vector<Case> out;
    Scene skin = load_scene("scenes/skin_slab.json");
    skin.visual_subdivisions = skin.collision_subdivisions = -1;
    out.push_back({"skin_slab", skin, tiny ? 30 : 200, all});
    if (!tiny) {
        Scene hand = load_scene("scenes/hand_dorsum.json");
        hand.visual_subdivisions = hand.collision_subdivisions = -1;
        out.push_back({"hand_dorsum", hand, 30, {"jacobi", "block_jacobi", "amg", "cholesky"}});
    }
    std::vector<std::string> with_plain = all;
    with_plain.push_back(std::string("cholesky") + kNoGuess);
    out.push_back({"block_2k", sized_scene("scenes/tissue_block.json", 2000), tiny ? 10 : 100, with_plain});
    if (!tiny) {
        out.push_back({"block_53k", sized_scene("scenes/tissue_block.json", 53000), 20,
                       {"jacobi", "block_jacobi", "amg", std::string("amg") + kNoGuess, "cholesky"}});
        out.push_back({"block_200k", sized_scene("scenes/tissue_block.json", 200000), 5,
                       {"jacobi", "block_jacobi", "amg", "cholesky"}});
    }
    out.push_back({"thin_membrane", thin_membrane(tiny), tiny ? 20 : 100, all});
    return out;
}

SolverBenchRow timed_once(const Case& c, const std::string& method, int threads) {
    set_thread_count(threads);
    Scene scene = c.scene;
    const size_t cut = method.find(kNoGuess);
    scene.solver.linear = method.substr(0, cut);
    if (cut != std::string::npos) scene.solver.guess_history = 0;
    SolverBenchRow r;
    r.case_name = c.name, r.method = method, r.threads = threads, r.guess_history = scene.solver.guess_history;
    auto sim = make_simulation(scene, false);
    const World& w = sim->world;
    r.tets = w.mesh_elements;
    const auto t0 = std::chrono::steady_clock::now();
    try {
        for (; r.steps < c.steps; ++r.steps) {
            step_simulation(*sim);
            r.cg_per_step += w.metrics.current.cg_iterations;
            r.max_residual = std::max(r.max_residual, w.metrics.current.cg_residual);
        }
    } catch (const NumericalError& e) {
        r.failure = e.what();
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const int done = std::max(1, r.steps);
    r.steps_per_s = r.steps / secs;
    r.ms_per_step = 1e3 * secs / done;
    r.cg_per_step /= done;
    r.refactored_steps = w.metrics.refactored_steps;
    r.substepped_steps = w.metrics.substepped_steps;
    r.factorizations = w.linear.factorizations;
    r.factor_bytes_per_tet = 12.0 * w.linear.factor_nonzeros / std::max(1, r.tets);
    r.rss_bytes_per_tet = peak_rss_bytes() / std::max(1, r.tets);
    r.load_setup_ms = w.linear.load_setup_ms;
    return r;
}

/// The case run `repeats` times from load: the run with the median rate, and the slowest and
/// fastest rates beside it. The host is shared (docs/BENCHMARKS.md, Noise): one run's rate moves by
/// 10-30 % with what else runs on it; the median of three is the figure, the spread is shown.
SolverBenchRow timed(const Case& c, const std::string& method, int threads, int repeats) {
    std::vector<SolverBenchRow> runs;
    for (int k = 0; k < repeats; ++k) runs.push_back(timed_once(c, method, threads));
    std::sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.steps_per_s < b.steps_per_s; });
    SolverBenchRow r = runs[runs.size() / 2];
    r.slowest_steps_per_s = runs.front().steps_per_s, r.fastest_steps_per_s = runs.back().steps_per_s;
    r.repeats = repeats;
    return r;
}

}  // namespace

std::vector<SolverBenchRow> run_solver_bench(const SolverBenchOptions& o) {
    std::vector<SolverBenchRow> rows;
    std::vector<Case> all = cases(o.tiny);
    if (!o.cases.empty())
        std::erase_if(all, [&](const Case& c) { return std::find(o.cases.begin(), o.cases.end(), c.name) == o.cases.end(); });
    if (all.empty()) throw InputError("--cases", "", "no such case in this configuration");
    for (const Case& c : all)
        for (const std::string& m : c.methods) {
            rows.push_back(timed(c, m, 2, o.repeats));
            if (o.progress) fmt::print(stderr, "  {} {}: {:.1f} steps/s\n", c.name, m, rows.back().steps_per_s);
        }
    // Under load: another process busy on one core; at 1 and 2 threads, the default scene with its
    // auto method (cholesky) and, in the full run, the 53k block with amg (the method whose cycle
    // has the most barriers).
    const int busy = start_busy_process();
    for (const Case& c : all) {
        const std::string method = c.name == "skin_slab" ? "cholesky" : c.name == "block_53k" ? "amg" : "";
        if (method.empty()) continue;
        for (int threads : {1, 2}) {
            SolverBenchRow r = timed(c, method, threads, o.repeats);
            r.case_name += "_loaded";
            rows.push_back(r);
        }
    }
    stop_busy_process(busy);
    set_thread_count(2);
    return rows;
}

int solver_bench_command(const SolverBenchOptions& o) {
    const std::vector<SolverBenchRow> rows = run_solver_bench(o);
    const std::string path = !o.csv.empty() ? o.csv : o.tiny ? "results/bench_solver_quick.csv" : "results/bench_solver.csv";
    auto csv = open_csv(path);
    csv.print("case,method,threads,tets,steps,steps_per_s,ms_per_step,cg_per_step,max_residual,refactored_steps,"
              "substepped_steps,factorizations,factor_bytes_per_tet,rss_bytes_per_tet,speedup_vs_jacobi,guess_history,"
              "load_setup_ms,repeats,slowest_steps_per_s,fastest_steps_per_s,failure\n");
    fmt::print("the factor's solves (cholesky) on the {} kernels\n", supernode_kernels<double>().name);
    fmt::print("{:<20} {:<16} {:>3} {:>7} {:>9} {:>15} {:>8} {:>9} {:>6} {:>6} {:>8} {:>9} {:>8}  {}\n", "case", "method",
               "thr", "tets", "steps/s", "(range)", "CG/step", "max res", "refac", "subst", "L B/tet", "vs jacobi",
               "setup ms", "");
    for (const SolverBenchRow& r : rows) {
        double jacobi = 0.0;
        for (const SolverBenchRow& j : rows)
            if (j.case_name == r.case_name && j.method == "jacobi" && j.failure.empty()) jacobi = j.steps_per_s;
        const double ratio = jacobi > 0 ? r.steps_per_s / jacobi : 0.0;
        const std::string failed = r.failure.empty() ? "" : "FAILED at step " + std::to_string(r.steps + 1);
        fmt::print("{:<20} {:<16} {:>3} {:>7} {:>9.1f} {:>15} {:>8.2f} {:>9.2e} {:>6} {:>6} {:>8.0f} {:>9} {:>8.1f}  {}\n",
                   r.case_name, r.method, r.threads, r.tets, r.steps_per_s,
                   fmt::format("({:.1f}-{:.1f})", r.slowest_steps_per_s, r.fastest_steps_per_s), r.cg_per_step, r.max_residual,
                   r.refactored_steps, r.substepped_steps, r.factor_bytes_per_tet,
                   ratio > 0 ? fmt::format("{:.2f}x", ratio) : "-", r.load_setup_ms, failed);
        std::string why = r.failure;
        for (char& ch : why)
            if (ch == '"' || ch == '\n') ch = '\'';
        csv.print("{},{},{},{},{},{:.3f},{:.3f},{:.2f},{:.3e},{},{},{},{:.1f},{:.1f},{:.3f},{},{:.1f},{},{:.3f},{:.3f},\"{}\"\n",
                  r.case_name, r.method, r.threads, r.tets, r.steps, r.steps_per_s, r.ms_per_step, r.cg_per_step,
                  r.max_residual, r.refactored_steps, r.substepped_steps, r.factorizations, r.factor_bytes_per_tet,
                  r.rss_bytes_per_tet, ratio, r.guess_history, r.load_setup_ms, r.repeats, r.slowest_steps_per_s,
                  r.fastest_steps_per_s, why);
    }
    fmt::print("targets (2 threads, tolerance as each scene sets it): skin_slab >= 200 steps/s and <= 5 CG/step; "
               "hand_dorsum no step over the cap, <= 1/4 of jacobi's step time; block_2k >= 1000 steps/s; block_53k "
               ">= 30 steps/s; thin_membrane converges every step; loaded: 2 threads <= 1.3x the 1-thread step "
               "(skin_slab cholesky, block_53k amg)\n");
    fmt::print("csv: {}\n", path);
    return 0;
}

}  // namespace xcut
