#include "engine/bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/os.h>
#include <fstream>

#include "engine/output.h"
#include "engine/parallel.h"
#include "engine/simulation.h"

namespace xcut {
namespace {

template <class T>
size_t bytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

double peak_rss_bytes() {
    std::ifstream in("/proc/self/status");
    std::string key;
    while (in >> key) {
        if (key == "VmHWM:") {
            double kb = 0;
            in >> kb;
            return kb * 1024.0;
        }
        std::getline(in, key);
    }
    return 0.0;
}

int system_index(const World& w, const std::string& name) {
    const auto& names = w.metrics.system_names;
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

}  // namespace

size_t world_bytes(const World& w) {
    const Nodes& n = w.nodes;
    const Elements& e = w.elements;
    const ForceState& f = w.forces;
    size_t b = bytes(n.rest) + bytes(n.position) + bytes(n.velocity) + bytes(n.mass) + bytes(n.fixed);
    b += bytes(e.nodes) + bytes(e.rest_volume) + bytes(e.dm_inv) + bytes(e.rotation) + bytes(e.material) + bytes(e.weight);
    b += bytes(w.incidence.offset) + bytes(w.incidence.entry) + bytes(w.virtual_incidence.offset) +
         bytes(w.virtual_incidence.entry);
    b += (f.force.size() + f.stiffness_diagonal.size() + f.last_dv.size()) * sizeof(double) + bytes(f.element_buffer);
    // The solver's per-step vectors (rhs, mass, preconditioner, mask, CG's four): 3 doubles each per node.
    b += 10 * 3 * sizeof(double) * static_cast<size_t>(n.count());
    return b;
}

std::vector<PerfBenchRow> run_perf_bench(const PerfBenchOptions& o, bool progress) {
    std::vector<PerfBenchRow> rows;
    ProgressBar bar("bench", progress ? static_cast<int>(o.sizes.size() * o.threads.size()) : 0);
    int done = 0;
    for (int target : o.sizes) {
        Scene scene = load_scene(o.scene);
        const Eigen::Vector3d size = scene.mesh.grid.size;
        scene.mesh.grid.cells = cells_for_size(size, std::cbrt(size.prod() * 6.0 / target));
        for (int threads : o.threads) {
            set_thread_count(threads);
            auto sim = make_simulation(scene, false);
            const World& w = sim->world;
            for (int i = 0; i < 2; ++i) step_simulation(*sim);
            PerfBenchRow r;
            r.tets = w.elements.count();
            r.nodes = w.nodes.count();
            r.threads = threads;
            const int fi = system_index(w, "ForceSystem"), si = system_index(w, "SolverSystem");
            long cg = 0;
            const auto t0 = std::chrono::steady_clock::now();
            for (int i = 0; i < o.steps; ++i) {
                step_simulation(*sim);
                const StepMetrics& m = w.metrics.current;
                cg += m.cg_iterations;
                if (fi >= 0) r.force_ms += m.system_ms[fi] / o.steps;
                if (si >= 0) r.solver_ms += m.system_ms[si] / o.steps;
            }
            const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            r.steps_per_s = o.steps / secs;
            r.ms_per_step = 1e3 * secs / o.steps;
            r.cg_per_step = static_cast<double>(cg) / o.steps;
            r.bytes_per_tet_components = static_cast<double>(world_bytes(w)) / r.tets;
            r.bytes_per_tet_rss = peak_rss_bytes() / r.tets;
            rows.push_back(r);
            bar.update(++done);
        }
    }
    bar.finish();
    set_thread_count(2);
    return rows;
}

int perf_bench_command(const PerfBenchOptions& o) {
    const auto rows = run_perf_bench(o);
    const std::filesystem::path csv_path(o.csv);
    if (csv_path.has_parent_path()) std::filesystem::create_directories(csv_path.parent_path());
    auto csv = fmt::output_file(o.csv);
    csv.print("tets,nodes,threads,steps_per_s,ms_per_step,cg_iter_per_step,force_ms,solver_ms,"
              "bytes_per_tet_components,bytes_per_tet_rss\n");
    fmt::print("perf benchmark: {} ({} timed steps per run, after 2 warm-up steps)\n", o.scene, o.steps);
    fmt::print("{:>8} {:>7} {:>7} {:>9} {:>9} {:>8} {:>9} {:>9} {:>10} {:>9} {:>8}\n", "tets", "nodes", "threads",
               "steps/s", "ms/step", "CG/step", "force ms", "solver ms", "B/tet comp", "B/tet RSS", "speed-up");
    for (const auto& r : rows) {
        double speedup = 0.0;
        for (const auto& s : rows)
            if (s.tets == r.tets && s.threads == 1) speedup = r.steps_per_s / s.steps_per_s;
        fmt::print("{:>8} {:>7} {:>7} {:>9.1f} {:>9.2f} {:>8.1f} {:>9.2f} {:>9.2f} {:>10.0f} {:>9.0f} {:>7.2f}x\n", r.tets,
                   r.nodes, r.threads, r.steps_per_s, r.ms_per_step, r.cg_per_step, r.force_ms, r.solver_ms,
                   r.bytes_per_tet_components, r.bytes_per_tet_rss, speedup);
        csv.print("{},{},{},{:.4f},{:.4f},{:.2f},{:.4f},{:.4f},{:.1f},{:.1f}\n", r.tets, r.nodes, r.threads,
                  r.steps_per_s, r.ms_per_step, r.cg_per_step, r.force_ms, r.solver_ms, r.bytes_per_tet_components,
                  r.bytes_per_tet_rss);
    }
    fmt::print("targets: >= 60 steps/s at 50k tets on 2 threads; >= 1.8x from 1 to 2 threads; <= 400 bytes per tet\n");
    fmt::print("csv: {}\n", o.csv);
    return 0;
}

}  // namespace xcut
