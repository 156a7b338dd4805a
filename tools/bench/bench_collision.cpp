#include "tools/bench/bench_collision.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>
#include <fstream>

#include "systems/pipeline.h"

namespace xcut {
namespace {

/// A 40 x 40 x 10 mm block (16 x 16 x 4 cells, 6144 tets) on a held bed, `tools` 4 mm probes each
/// pressing 1 mm into its top at spots 10 mm apart.
Scene pressed_block(int subdivisions, int tools, const std::string& dir) {
    std::string probes;
    for (int i = 0; i < tools; ++i) {
        const double x = 0.005 + 0.01 * (i % 4), y = 0.005 + 0.01 * (i / 4);
        probes += fmt::format(R"({}{{ "name": "probe{}", "shape": {{ "type": "sphere", "radius": 0.004 }},
            "contact": {{ "stiffness": 500 }},
            "trajectory": [ {{ "time": 0, "position": [{}, {}, 0.015] }}, {{ "time": 0.1, "position": [{}, {}, 0.013] }} ] }})",
                              i ? "," : "", i, x + 0.01, y + 0.01, x + 0.01, y + 0.01);
    }
    const std::string text = fmt::format(R"({{
  "mesh": {{ "generator": "box", "size": [0.04, 0.04, 0.01], "cells": [16, 16, 4] }},
  "material": {{ "young": 10000, "poisson": 0.3, "density": 1000 }},
  "constraints": {{ "fixed_boxes": [ {{ "min": [-1, -1, -1], "max": [1, 1, 1e-9] }} ] }},
  "collision": {{ "subdivisions": {} }},
  "tools": [ {} ],
  "solver": {{ "dt": 0.01, "cg_tolerance": 1e-6, "cg_max_iterations": 300, "damping": {{ "mass": 2 }} }},
  "steps": 10
}})",
                                         subdivisions, probes);
    const std::string file = dir + "/bench_collision_scene.json";
    std::ofstream(file) << text;
    return load_scene(file);
}

double collision_ms(const World& w) {
    const auto& names = w.metrics.system_names;
    const auto it = std::find(names.begin(), names.end(), "CollisionSystem");
    return it == names.end() ? 0.0 : w.metrics.current.system_ms[it - names.begin()];
}

}  // namespace

int collision_bench_command(const CollisionBenchOptions& o) {
    const std::filesystem::path path(o.csv);
    const std::string dir = path.has_parent_path() ? path.parent_path().string() : ".";
    std::filesystem::create_directories(dir);
    auto csv = fmt::output_file(o.csv);
    csv.print("subdivisions,collision_vertices,collision_triangles,tools,contacts,collision_ms_mean,collision_ms_max,step_ms_mean\n");
    fmt::print("collision benchmark: 6k-tet block pressed by 4 mm probes; CollisionSystem time per step\n");
    fmt::print("{:>5} {:>9} {:>9} {:>5} {:>8} {:>10} {:>10} {:>10}\n", "subdv", "vertices", "triangles", "tools",
               "contacts", "coll ms", "coll max", "step ms");
    for (int sub : o.subdivisions)
        for (int tools : o.tools) {
            auto sim = make_simulation(pressed_block(sub, tools, dir), false);
            for (int s = 0; s < 10; ++s) step_simulation(*sim);  // probes in contact
            double sum = 0.0, max = 0.0, step = 0.0;
            for (int s = 0; s < o.steps; ++s) {
                step_simulation(*sim);
                const double ms = collision_ms(sim->world);
                sum += ms, max = std::max(max, ms), step += sim->world.metrics.current.step_ms;
            }
            const SurfaceMesh& c = sim->world.collision;
            fmt::print("{:>5} {:>9} {:>9} {:>5} {:>8} {:>10.3f} {:>10.3f} {:>10.2f}\n", sub, c.vertex_count(),
                       c.triangles.size(), tools, sim->world.contacts.count(), sum / o.steps, max, step / o.steps);
            csv.print("{},{},{},{},{},{:.5f},{:.5f},{:.4f}\n", sub, c.vertex_count(), c.triangles.size(), tools,
                      sim->world.contacts.count(), sum / o.steps, max, step / o.steps);
        }
    // The haptic loop at 1 kHz beside the physics (4 probes, collision level 1).
    auto sim = make_simulation(pressed_block(1, 4, dir), false);
    std::vector<ToolDevice*> devices;
    for (auto& d : sim->devices) devices.push_back(d.get());
    HapticLoop loop(devices);
    sim->haptics = &loop;
    loop.start();
    for (int s = 0; s < o.haptic_steps; ++s) step_simulation(*sim);
    loop.stop();
    const HapticStats h = loop.stats();
    fmt::print("haptic loop beside {} physics steps: {} ticks in {:.2f} s = {:.0f} Hz (target 1000); period p50 {:.3f} ms, "
               "p99 {:.3f} ms, max {:.3f} ms\n",
               o.haptic_steps, h.ticks, h.seconds, h.rate_hz, h.period_p50_ms, h.period_p99_ms, h.period_max_ms);
    csv.print("# haptic,ticks={},seconds={:.3f},rate_hz={:.1f},period_p50_ms={:.4f},period_p99_ms={:.4f},period_max_ms={:.4f}\n",
              h.ticks, h.seconds, h.rate_hz, h.period_p50_ms, h.period_p99_ms, h.period_max_ms);
    return 0;
}

}  // namespace xcut
