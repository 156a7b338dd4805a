// xcut: command-line front end. `xcut run SCENE` steps a scene headless and writes its ParaView
// series and metrics CSV; the other subcommands arrive with their issues.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <exception>

#include "engine/bench.h"
#include "engine/bench_accuracy.h"
#include "engine/bench_collision.h"
#include "engine/bench_cut.h"
#include "engine/bench_mapping.h"
#include "engine/compare.h"
#include "engine/error.h"
#include "engine/render.h"
#include "engine/parallel.h"
#include "engine/simulation.h"
#include "engine/stress.h"
#include "systems/enrichment_system.h"

namespace {

struct RunOptions {
    std::string scene;
    int threads = 2;
    int steps = -1;
    std::string output;
    std::vector<std::string> overrides;
    bool quiet = false;
    std::string record, replay;  ///< session directories (engine/device.h)
    bool haptics = false;        ///< run the 1 kHz haptic loop beside the physics
    std::string cutter;   ///< --cutter: sets cutter.type
};

std::vector<std::string> overrides_of(const RunOptions& o) {
    std::vector<std::string> all = o.overrides;
    if (!o.cutter.empty()) all.push_back("cutter.type=\"" + o.cutter + "\"");
    return all;
}

void render_to(const xcut::Scene& scene, const xcut::World& w, const std::string& png) {
    const xcut::Camera cam = scene.camera.automatic ? xcut::frame_surface(w.visual, scene.camera.width, scene.camera.height)
                                                    : scene.camera;
    xcut::write_png(xcut::render_surface(w.visual, cam), png);
}

int render_command(const RunOptions& o, const std::string& png) {
    using namespace xcut;
    set_thread_count(o.threads);
    Scene scene = load_scene(o.scene, overrides_of(o));
    if (scene.visual_subdivisions < 0) scene.visual_subdivisions = 0;
    auto sim = make_simulation(scene, /*with_output=*/false);
    run_simulation(*sim, o.steps >= 0 ? o.steps : scene.steps, !o.quiet);
    const std::string out = png.empty() ? scene.name + ".png" : png;
    render_to(scene, sim->world, out);
    fmt::print("render: {} (t = {:.4g} s, {} triangles)\n", out, sim->world.time, sim->world.visual.triangles.size());
    return 0;
}

int run_command(const RunOptions& o) {
    using namespace xcut;
    set_thread_count(o.threads);
    Scene scene = load_scene(o.scene, overrides_of(o));
    if (!o.output.empty()) scene.output.directory = o.output;
    const int steps = o.steps >= 0 ? o.steps : scene.steps;
    auto sim = make_simulation(scene, true, o.replay);
    if (!o.record.empty()) sim->recorder = std::make_unique<SessionRecorder>(sim->world, o.record);
    std::unique_ptr<HapticLoop> haptics;
    if (o.haptics) {
        std::vector<ToolDevice*> devices;
        for (auto& d : sim->devices) devices.push_back(d.get());
        haptics = std::make_unique<HapticLoop>(devices);
        sim->haptics = haptics.get();
        haptics->start();
    }
    sim->world.verbose = true;
    const World& w = sim->world;
    fmt::print("scene {} ({}): {} nodes, {} {}, {} threads, dt {} s ({}), {} steps\n", scene.name, o.scene,
               w.nodes.count(), w.elements.count(), w.elements.dim == 3 ? "tetrahedra" : "triangles",
               thread_count(), w.solver.dt, w.solver.realtime ? "real-time" : "fixed", steps);
    fmt::print("{}", sim->scheduler.describe(w));
    const auto t0 = std::chrono::steady_clock::now();
    run_simulation(*sim, steps, !o.quiet);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (haptics) {
        haptics->stop();
        const HapticStats h = haptics->stats();
        fmt::print("haptics: {} ticks in {:.2f} s ({:.0f} Hz, target 1000); period p50 {:.3f} ms, p99 {:.3f} ms, max {:.3f} ms\n",
                   h.ticks, h.seconds, h.rate_hz, h.period_p50_ms, h.period_p99_ms, h.period_max_ms);
    }
    if (!o.record.empty()) fmt::print("session recorded: {}/<tool>.csv\n", o.record);
    const StepMetrics& m = w.metrics.current;
    double max_disp = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) max_disp = std::max(max_disp, (w.nodes.position[i] - w.nodes.rest[i]).norm());
    fmt::print("done: t = {:.4g} s in {:.3f} s wall ({:.1f} steps/s); DOFs {}; last step {} CG iterations; "
               "max displacement {:.4g} m; kinetic {:.4g} J, elastic {:.4g} J\n",
               w.time, secs, steps / std::max(secs, 1e-9), m.dofs, m.cg_iterations, max_disp, m.kinetic_energy,
               m.elastic_energy);
    if (w.cuts.count() > 0) {
        double opening = 0.0;
        for (int j = 0; j < w.mesh_nodes; ++j) opening = std::max(opening, xcut::enriched_displacement(w, j).norm());
        fmt::print("cut: {} elements split, {} enriched DOF nodes ({} held by the crack front), max opening |a_j| {:.4g} m\n",
                   w.cuts.count(), w.enriched.count(),
                   std::count(w.enriched.front_fixed.begin(), w.enriched.front_fixed.end(), 1), opening);
    }
    if (w.snap.elements_split > 0)
        fmt::print("cut (snap): {} elements split, {} nodes snapped (largest move {:.3g} m), {} edge points, {} copies\n",
                   w.snap.elements_split, w.snap.snaps, w.snap.max_snap_distance, w.snap.points, w.snap.copies);
    if (sim->output && w.visual.vertex_count() > 0) {
        const std::string png = sim->output->directory() + "/" + scene.name + ".png";
        render_to(scene, w, png);
        fmt::print("render: {}\n", png);
    }
    if (sim->output) fmt::print("output: {}/{}.pvd and {}_metrics.csv\n", sim->output->directory(), scene.name, scene.name);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"xcut: real-time cutting of soft tissue with the corotational XFEM"};
    app.require_subcommand(1);
    RunOptions run;
    CLI::App* run_cmd = app.add_subcommand("run", "Run a scene headless: ParaView series + metrics CSV");
    run_cmd->add_option("scene", run.scene, "Scene file (JSON, see docs/scene-format.md)")->required();
    run_cmd->add_option("--threads,-j", run.threads, "OpenMP threads (results are identical for any count)")
        ->check(CLI::Range(1, 256));
    run_cmd->add_option("--steps", run.steps, "Override the scene's step count")->check(CLI::NonNegativeNumber);
    run_cmd->add_option("--output,-o", run.output, "Output directory (default: the scene's output.directory)");
    run_cmd->add_option("--set", run.overrides, "Override a scene field: field.path=value (JSON value)");
    run_cmd->add_flag("--quiet,-q", run.quiet, "No progress bar");
    run_cmd->add_option("--record", run.record, "Record the tools' poses each step to DIR/<tool>.csv");
    run_cmd->add_option("--replay", run.replay, "Drive the tools from a session recorded with --record (bit-identical)");
    run_cmd->add_flag("--haptics", run.haptics, "Run the 1 kHz haptic loop beside the physics; report its rate and jitter");
    run_cmd->add_option("--cutter", run.cutter, "Cutter: xfem (default) or snap (snapping and subdivision)")
        ->check(CLI::IsMember({"xfem", "snap"}));
    RunOptions render;
    std::string png;
    CLI::App* render_cmd = app.add_subcommand("render", "Run a scene and render its visual surface to a PNG (Embree)");
    render_cmd->add_option("scene", render.scene, "Scene file")->required();
    render_cmd->add_option("--steps", render.steps, "Steps to run before rendering (default: the scene's)");
    render_cmd->add_option("--png,-o", png, "PNG to write (default: <scene name>.png)");
    render_cmd->add_option("--set", render.overrides, "Override a scene field: field.path=value");
    render_cmd->add_option("--threads,-j", render.threads, "OpenMP threads")->check(CLI::Range(1, 256));
    render_cmd->add_flag("--quiet,-q", render.quiet, "No progress bar");
    render_cmd->add_option("--cutter", render.cutter, "Cutter: xfem (default) or snap")->check(CLI::IsMember({"xfem", "snap"}));

    xcut::PerfBenchOptions perf;
    xcut::CutBenchOptions cut;
    std::string suite = "perf";
    CLI::App* bench_cmd = app.add_subcommand("bench", "Benchmarks: print figures and write CSV (never pass/fail)");
    bench_cmd->add_option("--suite", suite, "perf: steps/s, CG, bytes per tet; cut: cut update per quad, crossing delay; mapping: surface update and re-binding; collision: contact time per step, haptic rate; accuracy: error against run time, XFEM and snapping (VERIFICATION.md 3, 5, 6)")
        ->check(CLI::IsMember({"perf", "cut", "mapping", "collision", "accuracy"}));
    bench_cmd->add_option("--sizes", perf.sizes, "Target tetrahedron counts")->delimiter(',');
    bench_cmd->add_option("--threads", perf.threads, "Thread counts (perf)")->delimiter(',');
    bench_cmd->add_option("--steps", perf.steps, "Timed steps per run (perf)")->check(CLI::PositiveNumber);
    bench_cmd->add_option("--scene", perf.scene, "Scene whose mesh.grid is resized (perf)");
    bench_cmd->add_option("--csv", perf.csv, "CSV to write (default results/bench_<suite>.csv)");
    bench_cmd->add_option("--speed", cut.speed, "Blade speed [m/s] (cut)")->check(CLI::PositiveNumber);
    xcut::AccuracyBenchOptions accuracy;
    bool accuracy_tiny = false, accuracy_no_plots = false;
    bench_cmd->add_option("--problems", accuracy.problems, "VERIFICATION.md problems (accuracy): 3, 5, 6")->delimiter(',');
    bench_cmd->add_flag("--tiny", accuracy_tiny, "The small CI configuration (accuracy)");
    bench_cmd->add_option("--cache-dir", accuracy.cache_dir,
                          "Where the conforming reference of problem 5 is cached (accuracy; default <build>/accuracy_cache)");
    bench_cmd->add_flag("--no-plots", accuracy_no_plots, "CSV only (accuracy)");
    xcut::StressOptions stress;
    CLI::App* stress_cmd = app.add_subcommand("stress", "Stability stress suite (VERIFICATION.md 7-9); exit 1 if an invariant broke");
    stress_cmd->add_option("--count", stress.count, "Random blade trajectories (problem 8)")->check(CLI::NonNegativeNumber);
    stress_cmd->add_option("--budget", stress.budget_s, "Wall-time budget for problem 8 [s]")->check(CLI::PositiveNumber);
    stress_cmd->add_option("--seed", stress.seed, "Random seed (reproducible)");
    stress_cmd->add_option("--csv", stress.csv, "CSV of every case");
    xcut::CompareOptions cmp;
    bool no_delay = false, no_plots = false;
    CLI::App* compare_cmd = app.add_subcommand(
        "compare", "XFEM against snapping and subdivision on one scene: DOFs per cut, crossing delay, quality, step time (CSV + PNG in out/<scene>/compare)");
    compare_cmd->add_option("scene", cmp.scene, "Scene file with a bladed tool (its incision is repeated)")->required();
    compare_cmd->add_option("--cuts", cmp.cuts, "Incisions, one after another, offset sideways")->check(CLI::Range(1, 200));
    compare_cmd->add_option("--spacing", cmp.spacing, "Sideways distance between incisions [m] (default: automatic)")
        ->check(CLI::NonNegativeNumber);
    compare_cmd->add_option("--threads,-j", cmp.threads, "OpenMP threads")->check(CLI::Range(1, 256));
    compare_cmd->add_option("--output,-o", cmp.output, "Output directory (default out/<scene>/compare)");
    compare_cmd->add_option("--set", cmp.overrides, "Override a scene field: field.path=value");
    compare_cmd->add_flag("--no-delay-sweep", no_delay, "Skip the crossing-delay sweep (blade speeds x mesh sizes)");
    compare_cmd->add_flag("--no-plots", no_plots, "CSVs only");
    compare_cmd->add_flag("--quiet,-q", cmp.quiet, "No progress bars");
    CLI11_PARSE(app, argc, argv);
    try {
        if (run_cmd->parsed()) return run_command(run);
        if (render_cmd->parsed()) return render_command(render, png);
        if (stress_cmd->parsed()) return xcut::stress_command(stress);
        if (compare_cmd->parsed()) {
            cmp.delay_sweep = !no_delay;
            cmp.plots = !no_plots;
            return xcut::compare_command(cmp);
        }
        if (bench_cmd->parsed()) {
            if (suite == "mapping") {
                xcut::MappingBenchOptions m;
                m.threads = perf.threads;
                if (bench_cmd->count("--csv")) m.csv = perf.csv;
                return xcut::mapping_bench_command(m);
            }
            if (suite == "collision") {
                xcut::CollisionBenchOptions c;
                if (bench_cmd->count("--csv")) c.csv = perf.csv;
                if (bench_cmd->count("--steps")) c.steps = perf.steps;
                return xcut::collision_bench_command(c);
            }
            if (suite == "accuracy") {
                xcut::AccuracyBenchOptions a = accuracy_tiny ? xcut::AccuracyBenchOptions::tiny() : xcut::AccuracyBenchOptions{};
                a.problems = accuracy.problems;
                a.cache_dir = accuracy.cache_dir;
                a.plots = !accuracy_no_plots;
                a.progress = true;
                if (bench_cmd->count("--threads")) a.threads = perf.threads.front();
                if (bench_cmd->count("--csv")) a.csv = perf.csv;
                return xcut::accuracy_bench_command(a);
            }
            if (suite == "cut") {
                cut.sizes = perf.sizes;
                cut.csv = bench_cmd->count("--csv") ? perf.csv : "results/bench_cut.csv";
                return xcut::cut_bench_command(cut);
            }
            return xcut::perf_bench_command(perf);
        }
    } catch (const xcut::InputError& e) {
        fmt::print(stderr, "error: {}\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        fmt::print(stderr, "error: {}\n", e.what());
        return 1;
    }
    return 0;
}
