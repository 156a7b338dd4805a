#include "tools/bench/bench_cutforce.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "engine/io/scene.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "tools/bench/bench.h"

namespace xcut {
namespace {

constexpr double kToughness = 200.0;          // [J/m^2] porcine liver, blade: 187-225 (docs/cutting-force.md)
constexpr double kTop = 0.03, kLength = 0.06;  // block top [m], extent along the cut [m]

/// The block and a scalpel whose edge reaches `depth` below the top, drawn along x at `speed`.
Scene scene_for(double speed, double depth) {
    const double x0 = -0.005, x1 = kLength + 0.005, t1 = (x1 - x0) / speed;
    const std::string text = fmt::format(R"({{
  "name": "cutforce",
  "mesh": {{"generator": "box", "origin": [0, 0, 0], "size": [{}, 0.04, {}], "element_size": 0.003}},
  "material": {{"name": "liver", "young": 5000, "poisson": 0.45, "density": 1060, "toughness": {}}},
  "allow": ["poisson"],
  "gravity": [0, 0, -9.81],
  "constraints": {{"fixed_boxes": [{{"min": [-1, -1, -1], "max": [1, 1, 1e-9]}}]}},
  "solver": {{"dt": 0.01, "damping": {{"mass": 1.0}}}},
  "tools": [{{"name": "scalpel", "blade": {{"tip": [0, 0, {}], "heel": [0, 0, 0.01]}},
             "trajectory": [{{"time": 0, "position": [{}, 0.0201, {}]}}, {{"time": {}, "position": [{}, 0.0201, {}]}}]}}],
  "steps": {}
}})",
                                         kLength, kTop, kToughness, -depth, x0, kTop, t1, x1, kTop,
                                         static_cast<int>(std::ceil(t1 / 0.01)));
    return load_scene_text(text, "cutforce", ".");
}

CutForceBenchRow run_case(double speed, double depth) {
    CutForceBenchRow r;
    r.speed = speed, r.depth = depth;
    set_thread_count(2);
    const Scene scene = scene_for(speed, depth);
    auto sim = make_simulation(scene, false);
    World& w = sim->world;
    std::vector<double> force, depth_seen;
    double previous = -1.0, total_ms = 0.0;
    for (int i = 0; i < scene.steps; ++i) {
        step_simulation(*sim);
        total_ms += w.metrics.current.step_ms;
        const double x = w.tools.position[0].x(), f = -w.tools.cutting_force[0].x();
        if (x < 0.25 * kLength || x > 0.75 * kLength) continue;
        force.push_back(f), depth_seen.push_back(w.tools.blade_depth[0]);
        if (previous >= 0.0) r.max_jump = std::max(r.max_jump, std::abs(f - previous));
        previous = f;
    }
    r.steps = scene.steps, r.steady_steps = static_cast<int>(force.size());
    r.ms_per_step = total_ms / std::max(1, scene.steps);
    r.elements_split = w.cuts.count();
    double sum = 0.0, sum_depth = 0.0;
    for (size_t k = 0; k < force.size(); ++k) sum += force[k], sum_depth += depth_seen[k];
    const double n = std::max<double>(1.0, force.size());
    r.mean_force = sum / n, r.mean_depth = sum_depth / n;
    double var = 0.0;
    for (double f : force) var += (f - r.mean_force) * (f - r.mean_force);
    r.std_force = std::sqrt(var / n);
    r.force_per_depth = r.mean_depth > 0.0 ? r.mean_force / r.mean_depth : 0.0;
    return r;
}

}  // namespace

std::vector<CutForceBenchRow> run_cutforce_bench(const CutForceBenchOptions& o) {
    const std::vector<double> speeds = o.tiny ? std::vector<double>{0.01, 0.05} : std::vector<double>{0.005, 0.01, 0.02, 0.05};
    const std::vector<double> depths = o.tiny ? std::vector<double>{0.006} : std::vector<double>{0.003, 0.006, 0.012};
    std::vector<CutForceBenchRow> rows;
    for (double d : depths)
        for (double v : speeds) {
            rows.push_back(run_case(v, d));
            fmt::print(stderr, "  depth {:.0f} mm, {:.0f} mm/s: {:.3f} N\n", 1e3 * d, 1e3 * v, rows.back().mean_force);
        }
    return rows;
}

int cutforce_bench_command(const CutForceBenchOptions& o) {
    const std::vector<CutForceBenchRow> rows = run_cutforce_bench(o);
    auto csv = open_csv(o.csv);
    csv.print("speed_mm_s,depth_mm,steps,steady_steps,mean_force_N,std_force_N,max_jump_N,mean_depth_mm,"
              "force_per_depth_N_m,toughness_J_m2,elements_split,ms_per_step\n");
    fmt::print("cutting force: a scalpel across a liver-like block (toughness {} J/m^2), steady part of the cut\n",
               kToughness);
    fmt::print("{:>8} {:>8} {:>9} {:>9} {:>9} {:>10} {:>10} {:>7} {:>8}\n", "speed", "depth", "force", "std", "max jump",
               "depth seen", "F/depth", "splits", "ms/step");
    for (const CutForceBenchRow& r : rows) {
        fmt::print("{:>5.0f}mm/s {:>5.0f}mm {:>8.3f}N {:>8.4f}N {:>8.4f}N {:>8.2f}mm {:>7.1f}N/m {:>7} {:>8.2f}\n",
                   1e3 * r.speed, 1e3 * r.depth, r.mean_force, r.std_force, r.max_jump, 1e3 * r.mean_depth,
                   r.force_per_depth, r.elements_split, r.ms_per_step);
        csv.print("{:.1f},{:.1f},{},{},{:.6f},{:.6f},{:.6f},{:.4f},{:.3f},{},{},{:.4f}\n", 1e3 * r.speed, 1e3 * r.depth,
                  r.steps, r.steady_steps, r.mean_force, r.std_force, r.max_jump, 1e3 * r.mean_depth, r.force_per_depth,
                  kToughness, r.elements_split, r.ms_per_step);
    }
    // Speed independence at each depth: the spread of the mean force across the speeds.
    for (size_t i = 0; i < rows.size();) {
        size_t j = i;
        double lo = rows[i].mean_force, hi = lo;
        for (; j < rows.size() && rows[j].depth == rows[i].depth; ++j)
            lo = std::min(lo, rows[j].mean_force), hi = std::max(hi, rows[j].mean_force);
        fmt::print("depth {:.0f} mm: mean force {:.3f}-{:.3f} N across speeds (spread {:.1f} %)\n", 1e3 * rows[i].depth, lo,
                   hi, lo > 0 ? 100.0 * (hi / lo - 1.0) : 0.0);
        i = j;
    }
    fmt::print("published (docs/cutting-force.md): porcine liver cut by a blade 187-225 J/m^2, i.e. {:.2f}-{:.2f} N per "
               "10 mm of edge; forces independent of speed (Greenish et al. 2002)\ncsv: {}\n", 187.0 * 0.01,
               225.0 * 0.01, o.csv);
    return 0;
}

}  // namespace xcut
