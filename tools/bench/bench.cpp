#include "tools/bench/bench.h"

#include <malloc.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <thread>

#include "tools/bench/bench_cut.h"
#include "tools/bench/bench_kernel.h"
#include "tools/bench/bench_skip.h"
#include "tools/bench/force_kernel_model.h"
#include "engine/io/output.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "systems/force_system.h"

namespace xcut {
namespace {

template <class T>
size_t bytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

/// The 1-minute load average: a run measured while other work shares the cores is noisy.
double load_average() {
    std::ifstream in("/proc/loadavg");
    double load = 0.0;
    in >> load;
    return load;
}

double system_ms(const PerfBenchRow& r, const std::string& name) {
    const auto it = std::find(r.system_names.begin(), r.system_names.end(), name);
    return it == r.system_names.end() ? 0.0 : r.system_ms[it - r.system_names.begin()];
}

/// Mean time of the CG's product K p on the world as it stands [ms] (p: the velocities).
double time_stiffness_product(World& w) {
    constexpr int kRepeats = 10;
    const Eigen::VectorXd p = Eigen::Map<const Eigen::VectorXd>(w.nodes.velocity.data()->data(), 3 * w.nodes.count());
    Eigen::VectorXd out;
    const StepOperator op = xcut_step_terms();
    op.stiffness_product(w, p, out);  // warm: buffers sized
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kRepeats; ++i) op.stiffness_product(w, p, out);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / kRepeats;
}

/// One timed run: `steps` steps after 2 warm-up steps of the scene on `threads` threads.
PerfBenchRow timed_run(const Scene& scene, int threads, int steps) {
    set_thread_count(threads);
    auto sim = make_simulation(scene, false);
    const World& w = sim->world;
    for (int i = 0; i < 2; ++i) step_simulation(*sim);
    PerfBenchRow r;
    r.tets = w.elements.count();
    r.nodes = w.nodes.count();
    r.threads = threads;
    r.system_names = w.metrics.system_names;
    r.system_ms.assign(r.system_names.size(), 0.0);
    long cg = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < steps; ++i) {
        step_simulation(*sim);
        const StepMetrics& m = w.metrics.current;
        cg += m.cg_iterations;
        for (size_t s = 0; s < r.system_ms.size(); ++s) r.system_ms[s] += m.system_ms[s] / steps;
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.steps_per_s = steps / secs;
    r.ms_per_step = 1e3 * secs / steps;
    r.cg_per_step = static_cast<double>(cg) / steps;
    r.force_ms = system_ms(r, "ForceSystem");
    r.solver_ms = system_ms(r, "SolverSystem");
    r.bytes_per_tet_components = static_cast<double>(world_bytes(w)) / r.tets;
    r.bytes_per_tet_rss = peak_rss_bytes() / r.tets;
    r.load_average = load_average();
    r.newton_iterations = mean_newton_iterations(w);
    r.product_ms = time_stiffness_product(sim->world);
    return r;
}

double speedup(const std::vector<PerfBenchRow>& rows, const PerfBenchRow& r) {
    for (const auto& s : rows)
        if (s.tets == r.tets && s.threads == 1) return r.steps_per_s / s.steps_per_s;
    return 0.0;
}

void write_steps_table(const PerfBenchOptions& o, const std::vector<PerfBenchRow>& rows) {
    auto csv = open_csv(o.csv);
    csv.print("tets,nodes,threads,steps_per_s,ms_per_step,cg_iter_per_step,force_ms,solver_ms,"
              "bytes_per_tet_components,bytes_per_tet_rss,speedup,load_average\n");
    fmt::print("perf benchmark: {} ({} timed steps per run, after 2 warm-up steps)\n", o.scene, o.steps);
    fmt::print("{:>8} {:>7} {:>7} {:>9} {:>9} {:>8} {:>9} {:>9} {:>10} {:>9} {:>8}\n", "tets", "nodes", "threads",
               "steps/s", "ms/step", "CG/step", "force ms", "solver ms", "B/tet comp", "B/tet RSS", "speed-up");
    for (const auto& r : rows) {
        const double s = speedup(rows, r);
        fmt::print("{:>8} {:>7} {:>7} {:>9.1f} {:>9.2f} {:>8.1f} {:>9.2f} {:>9.2f} {:>10.0f} {:>9.0f} {:>7.2f}x\n", r.tets,
                   r.nodes, r.threads, r.steps_per_s, r.ms_per_step, r.cg_per_step, r.force_ms, r.solver_ms,
                   r.bytes_per_tet_components, r.bytes_per_tet_rss, s);
        csv.print("{},{},{},{:.4f},{:.4f},{:.2f},{:.4f},{:.4f},{:.1f},{:.1f},{:.3f},{:.2f}\n", r.tets, r.nodes, r.threads,
                  r.steps_per_s, r.ms_per_step, r.cg_per_step, r.force_ms, r.solver_ms, r.bytes_per_tet_components,
                  r.bytes_per_tet_rss, s, r.load_average);
    }
    const auto busiest = std::max_element(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
        return a.load_average < b.load_average;
    });
    if (busiest != rows.end() && busiest->load_average > 1.0 + busiest->threads)
        fmt::print("note: load average up to {:.1f} on {} cores during the runs: other work shared the machine, "
                   "the figures are noisy\n",
                   busiest->load_average, std::thread::hardware_concurrency());
    fmt::print("targets: >= 60 steps/s at 50k tets and >= 1000 steps/s at 2k tets on 2 threads; >= 1.8x from 1 to 2 "
               "threads; <= 400 bytes per tet\n");
}

/// Time per scheduled system, long format: one row per (size, threads, system).
void write_systems_table(const PerfBenchOptions& o, const std::vector<PerfBenchRow>& rows) {
    const std::string path = sibling_csv(o.csv, "systems");
    auto csv = open_csv(path);
    csv.print("tets,threads,system,ms_per_step,share_of_step\n");
    fmt::print("\ntime per system [ms per step] (share of the step)\n");
    for (const auto& r : rows) {
        fmt::print("{:>8} tets, {} thread{}:", r.tets, r.threads, r.threads == 1 ? " " : "s");
        for (size_t s = 0; s < r.system_names.size(); ++s) {
            const double share = r.system_ms[s] / r.ms_per_step;
            fmt::print("  {} {:.3f} ({:.0f}%)", r.system_names[s], r.system_ms[s], 100.0 * share);
            csv.print("{},{},{},{:.5f},{:.5f}\n", r.tets, r.threads, r.system_names[s], r.system_ms[s], share);
        }
        fmt::print("\n");
    }
}

void cut_update_rows(const PerfBenchOptions& o) {
    std::vector<CutBenchRow> rows;
    ProgressBar bar("cut", static_cast<int>(o.sizes.size()));
    CutBenchOptions c;
    for (int target : o.sizes) {
        c.sizes = {target};
        for (const auto& r : run_cut_bench(c)) rows.push_back(r);
        bar.update(static_cast<int>(rows.size()));
    }
    bar.finish();
    fmt::print("\ncut update against mesh size (neighbourhood search; tools/bench/bench_cut.h)\n");
    write_cut_rows(rows, sibling_csv(o.csv, "cut"));
    fmt::print("target: <= 1 ms p99 cut update at 50k tets\n");
}

}  // namespace

bool reset_peak_rss() {
    malloc_trim(0);  // what earlier runs freed goes back to the system, out of the next run's peak
    std::ofstream out("/proc/self/clear_refs");
    out << "5";
    return static_cast<bool>(out.flush());
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

Scene sized_scene(const std::string& path, int tets, const std::vector<std::string>& overrides) {
    Scene scene = load_scene(path, overrides);
    const Eigen::Vector3d size = scene.mesh.grid.size;
    scene.mesh.grid.cells = cells_for_size(size, std::cbrt(size.prod() * 6.0 / tets));
    return scene;
}

std::string sibling_csv(const std::string& csv, const std::string& part) {
    const std::filesystem::path p(csv);
    return (p.parent_path() / (p.stem().string() + "_" + part + p.extension().string())).string();
}

fmt::ostream open_csv(const std::string& path) {
    const std::filesystem::path p(path);
    if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
    return fmt::output_file(path);
}

std::vector<PerfBenchRow> run_perf_bench(const PerfBenchOptions& o, bool progress) {
    std::vector<PerfBenchRow> rows;
    ProgressBar bar("bench", progress ? static_cast<int>(o.sizes.size() * o.threads.size()) : 0);
    for (int target : o.sizes) {
        const Scene scene = sized_scene(o.scene, target);
        for (int threads : o.threads) {
            rows.push_back(timed_run(scene, threads, o.steps));
            bar.update(static_cast<int>(rows.size()));
        }
    }
    bar.finish();
    set_thread_count(2);
    return rows;
}

int perf_bench_command(const PerfBenchOptions& o) {
    const auto rows = run_perf_bench(o);
    write_steps_table(o, rows);
    write_systems_table(o, rows);
    kernel_against_roofline(rows, o);
    if (o.cut_rows) cut_update_rows(o);
    skip_row(o);
    fmt::print("csv: {} and {}_*.csv\n", o.csv, std::filesystem::path(o.csv).replace_extension().string());
    return 0;
}

int start_busy_process() {
    const pid_t pid = fork();
    if (pid == 0) {
        volatile double x = 0.0;
        for (;;) x = x * 0.999 + 1.0;
    }
    return pid;
}

void stop_busy_process(int pid) {
    if (pid > 0) kill(pid, SIGKILL), waitpid(pid, nullptr, 0);
}

}  // namespace xcut
