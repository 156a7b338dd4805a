#include "tools/bench/bench_cut.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <fmt/os.h>

#include "tools/bench/bench.h"
#include "systems/kernels/element_bvh.h"
#include "engine/io/generators.h"
#include "engine/setup.h"
#include "systems/cut/cut_system.h"
#include "systems/cut/enrichment_system.h"
#include "systems/tool_system.h"

namespace xcut {
double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t i = std::min(v.size() - 1, static_cast<size_t>(std::ceil(p * v.size())) - (p > 0 ? 1 : 0));
    return v[i];
}

World block_with_scalpel(int tets, double speed) {
    const Vec3 size(0.1, 0.1, 0.05);
    const double h = std::cbrt(size.prod() * 6.0 / tets);
    GridSpec g;
    g.size = size;
    g.cells = cells_for_size(size, h);
    World w;
    w.materials.list = {Material{}};
    build_bodies(w, generate_box(g));
    Keyframe a, b;
    a.position = Vec3(0.0, 0.0503, 0.05);
    b.position = Vec3(0.1, 0.0503, 0.05);
    b.time = 0.1 / speed;
    add_scalpel(w, "scalpel", {a, b}, Vec3(0, 0, -0.02), Vec3(0, 0, 0.005));
    return w;
}

namespace {

/// Two more scalpels for the recut row, each drawn when the one before has finished: across the
/// first wound along y, then along the diagonal through the crossing, so the elements about the
/// crossing are cut two and three times.
void add_crossing_scalpels(World& w, double speed) {
    const double T = 0.1 / speed;
    Keyframe a, b, c, d;
    a.position = Vec3(0.0503, 0.0, 0.05), a.time = T;
    b.position = Vec3(0.0503, 0.1, 0.05), b.time = 2.0 * T;
    c.position = Vec3(0.0, 0.0, 0.05), c.time = 2.0 * T;
    d.position = Vec3(0.1, 0.1, 0.05), d.time = 2.0 * T + std::sqrt(2.0) * T;
    add_scalpel(w, "across", {a, b}, Vec3(0, 0, -0.02), Vec3(0, 0, 0.005));
    add_scalpel(w, "diagonal", {c, d}, Vec3(0, 0, -0.02), Vec3(0, 0, 0.005));
}

/// Mesh elements whose cut holds more than one line (cut again) [-].
int elements_cut_again(const World& w) {
    int n = 0;
    for (const auto& lines : w.cuts.lines) n += lines.size() > 1;
    return n;
}

}  // namespace

std::vector<CutBenchRow> run_cut_bench(const CutBenchOptions& o) {
    using Clock = std::chrono::steady_clock;
    std::vector<CutBenchRow> rows;
    for (int target : o.sizes) {
        World w = block_with_scalpel(target, o.speed);
        if (o.recut) add_crossing_scalpels(w, o.speed), w.cut_state.recut = 1;
        ElementBvh bvh;
        prepare_cut_search(w, bvh);  // at scene load, as `xcut run` does
        prepare_enrichment(w);
        w.cut_state.bvh_every_quad = o.bvh_every_quad;
        CutBenchRow row;
        row.search = o.recut ? "recut" : o.bvh_every_quad ? "bvh" : "neighbourhood";
        row.tets = w.mesh_elements;
        std::vector<double> update_ms;
        const double t_end = (o.recut ? 2.0 + std::sqrt(2.0) : 1.0) * 0.1 / o.speed + o.dt;
        for (double t = 0.0; t <= t_end; t += o.dt) {
            w.time = t;
            advance_tools(w, t);
            const auto t0 = Clock::now();
            run_cut_system(w, bvh);
            const auto t1 = Clock::now();
            apply_cut_events(w);
            const auto t2 = Clock::now();
            const double cutter = std::chrono::duration<double, std::milli>(t1 - t0).count();
            const double enrichment = std::chrono::duration<double, std::milli>(t2 - t1).count();
            if (w.cut_state.quads_built > 0) {
                update_ms.push_back(cutter + enrichment);
                if (cutter + enrichment > row.update_max_ms)
                    row.update_max_ms = cutter + enrichment, row.worst_cutter_ms = cutter, row.worst_enrichment_ms = enrichment;
            }
            row.splits += w.cut_state.elements_split;
        }
        const CutState& cs = w.cut_state;
        row.quads = static_cast<int>(cs.quad_ms.size());
        // The first quad builds the Embree BVH (first contact); it is reported within p99.
        row.quad_p50_ms = percentile(cs.quad_ms, 0.5);
        row.quad_p99_ms = percentile(cs.quad_ms, 0.99);
        row.update_p50_ms = percentile(update_ms, 0.5);
        row.update_p99_ms = percentile(update_ms, 0.99);
        row.delay_p50_s = percentile(cs.delay_sim, 0.5);
        row.delay_p99_s = percentile(cs.delay_sim, 0.99);
        row.cut_again = elements_cut_again(w);
        rows.push_back(row);
    }
    return rows;
}

void write_cut_rows(const std::vector<CutBenchRow>& rows, const std::string& path) {
    auto csv = open_csv(path);
    csv.print("search,tets,quads,splits,cut_again,quad_p50_ms,quad_p99_ms,update_p50_ms,update_p99_ms,delay_p50_s,delay_p99_s,"
              "update_max_ms,worst_cutter_ms,worst_enrichment_ms\n");
    fmt::print("{:>13} {:>8} {:>6} {:>7} {:>9} {:>10} {:>10} {:>11} {:>11} {:>10} {:>10} {:>22}\n", "search", "tets", "quads",
               "splits", "cut again", "quad p50", "quad p99", "update p50", "update p99", "delay p50", "delay p99",
               "worst: cutter + enrich.");
    for (const auto& r : rows) {
        fmt::print("{:>13} {:>8} {:>6} {:>7} {:>9} {:>8.3f}ms {:>8.3f}ms {:>9.3f}ms {:>9.3f}ms {:>9.3f}s {:>9.3f}s {:>7.3f} + {:.3f} ms\n",
                   r.search, r.tets, r.quads, r.splits, r.cut_again, r.quad_p50_ms, r.quad_p99_ms, r.update_p50_ms,
                   r.update_p99_ms, r.delay_p50_s, r.delay_p99_s, r.worst_cutter_ms, r.worst_enrichment_ms);
        csv.print("{},{},{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", r.search, r.tets, r.quads,
                  r.splits, r.cut_again, r.quad_p50_ms, r.quad_p99_ms, r.update_p50_ms, r.update_p99_ms, r.delay_p50_s,
                  r.delay_p99_s, r.update_max_ms, r.worst_cutter_ms, r.worst_enrichment_ms);
    }
}

int cut_bench_command(const CutBenchOptions& o) {
    // Both candidate searches, so the choice of the default (the neighbourhood) stays measured.
    auto rows = run_cut_bench(o);
    CutBenchOptions with_bvh = o;
    with_bvh.bvh_every_quad = true;
    for (const auto& r : run_cut_bench(with_bvh)) rows.push_back(r);
    // Several cuts per element (3D, cutter.recut on): three scalpels, the second across the first's
    // wound and the third through the crossing; the update over all their quads.
    CutBenchOptions recut = o;
    recut.recut = true;
    for (const auto& r : run_cut_bench(recut)) rows.push_back(r);
    fmt::print("cut benchmark: blade {} m/s, dt {} s (CutSystem per quad; update = CutSystem + EnrichmentSystem)\n",
               o.speed, o.dt);
    write_cut_rows(rows, o.csv);
    fmt::print("target: <= 1 ms p99 per quad at 50k tets (also where elements are cut again), growth with mesh size close to "
               "flat\n");
    return 0;
}

}  // namespace xcut
