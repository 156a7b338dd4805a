// xcut run SCENE: step a scene headless; ParaView series, metrics CSV and a PNG of the surface.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include "engine/error.h"
#include "engine/io/scene_checks.h"
#include "engine/parallel.h"
#include "systems/kernels/solver/supernode_solve.h"
#include "systems/pipeline.h"
#include "systems/solver/cholesky_factor.h"
#include "tools/xcut_commands.h"
#include "tools/xcut_run_summary.h"

namespace xcut {
namespace {

struct RunOptions {
    SceneOptions scene;
    std::string output;
    std::string record, replay;  ///< session directories (engine/devices/device.h)
    bool haptics = false;        ///< run the 1 kHz haptic loop beside the physics
    std::string summary;         ///< --summary FILE: the final figures as JSON
    bool no_output = false;      ///< --no-output: no series, CSV, surfaces or picture
};

/// Prints each as a warning and keeps it for the summary.
void warn_all(const std::vector<std::string>& notes, std::vector<std::string>& kept) {
    for (const std::string& note : notes) {
        fmt::print(stderr, "warning: {}\n", note);
        kept.push_back(note);
    }
}

int run_scene(const RunOptions& o, RunSummary& summary) {
    set_thread_count(o.scene.threads);
    std::vector<std::string> overrides = o.scene.all_overrides();
    if (!o.replay.empty()) {  // the session's overrides (its command line's, the viewer's tools) last: they win
        std::vector<std::string> session = read_session_overrides(o.replay);
        overrides.insert(overrides.end(), session.begin(), session.end());
    }
    Scene scene = load_scene(o.scene.scene, overrides);
    summary.name = scene.name;
    if (!o.output.empty()) scene.output.directory = o.output;
    if (o.no_output) scene.output.directory.clear();
    // A replay runs to the end of its recording (a session recorded past the scene's duration
    // holds what was done there); --steps still decides when given.
    const int recorded = o.replay.empty() ? 0 : static_cast<int>(read_session_steps(o.replay).size());
    const int steps = o.scene.steps >= 0 ? o.scene.steps : recorded > 0 ? recorded : scene.steps;
    if (o.scene.steps < 0 && recorded > 0 && recorded != scene.steps)
        fmt::print("replay: {} steps, as recorded (the scene says {})\n", recorded, scene.steps);
    scene.steps = steps;  // what the run takes: the output's bound is checked against it
    auto sim = make_simulation(scene, !o.no_output, o.replay);
    if (!o.record.empty()) sim->recorder = std::make_unique<SessionRecorder>(sim->world, o.record, SessionInfo{o.scene.scene, overrides});
    std::unique_ptr<HapticLoop> haptics = start_haptics(*sim, o.haptics);
    sim->world.verbose = true;
    const World& w = sim->world;
    const char* wait = std::getenv("OMP_WAIT_POLICY");
    const char* tunables = std::getenv("GLIBC_TUNABLES");  // engine/startup_environment.h
    const bool huge = tunables && std::string(tunables).find("glibc.malloc.hugetlb=0") == std::string::npos &&
                      std::string(tunables).find("glibc.malloc.hugetlb=") != std::string::npos;
    fmt::print("scene {} ({}): {} nodes, {} {}, {} threads (OpenMP wait {}; malloc huge pages {}), dt {} s ({}), {} "
               "steps\n",
               scene.name, o.scene.scene, w.nodes.count(), w.elements.count(),
               w.elements.dim == 3 ? "tetrahedra" : "triangles", configured_thread_count(), wait ? wait : "active",
               huge ? "on" : "off", w.solver.dt, w.solver.realtime ? "real-time" : "fixed", steps);
    warn_all(w.mesh_notes, summary.warnings);
    warn_all(plausibility_warnings(scene, w, steps), summary.warnings);
    fmt::print("{}", sim->scheduler.describe(w));
    if (w.linear.load_setup_ms > 0.0) {
        const LinearFactor* f = w.linear.method == "amg" ? nullptr : w.linear.factor.get();
        const std::string size = !f ? std::string()
                                    : fmt::format(" (L {:.3g} M non-zeros, solved in {} precision{})", f->lnz / 1e6,
                                                  f->lower && f->lower->is_single() ? "single" : "double",
                                                  f->lower ? std::string(", ") + supernode_kernels<double>().name + " kernels" : "");
        fmt::print("linear solver: {} built at load in {:.0f} ms{}\n",
                   w.linear.method == "amg" ? "the multigrid hierarchy" : "the Cholesky factor", w.linear.load_setup_ms, size);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    try {
        run_simulation(*sim, steps, !o.scene.quiet);
    } catch (const NumericalError&) {  // the figures the run reached, for the summary
        summary.has_figures = true;
        summary.figures = run_figures(w, sim->steps_done, seconds());
        throw;
    }
    const double secs = seconds();
    if (haptics) {
        haptics->stop();
        const HapticStats h = haptics->stats();
        fmt::print("haptics: {} ticks in {:.2f} s ({:.0f} Hz, target 1000); period p50 {:.3f} ms, p99 {:.3f} ms, max {:.3f} ms\n",
                   h.ticks, h.seconds, h.rate_hz, h.period_p50_ms, h.period_p99_ms, h.period_max_ms);
    }
    if (!o.record.empty()) fmt::print("session recorded: {}/<tool>.csv\n", o.record);
    summary.has_figures = true;
    summary.figures = run_figures(w, steps, secs);
    print_figures(summary.figures, w.metrics.max_substeps);
    if (w.snap.elements_split > 0)
        fmt::print("cut (snap): {} elements split, {} nodes snapped (largest move {:.3g} m), {} edge points, {} copies\n",
                   w.snap.elements_split, w.snap.snaps, w.snap.max_snap_distance, w.snap.points, w.snap.copies);
    warn_all(end_of_run_notes(w), summary.warnings);
    if (sim->output && w.visual.vertex_count() > 0) {
        const std::string png = sim->output->directory() + "/" + scene.name + ".png";
        render_scene_png(scene, w, png);
        fmt::print("render: {}\n", png);
    }
    if (sim->output) fmt::print("output: {}/{}.pvd and {}_metrics.csv\n", sim->output->directory(), scene.name, scene.name);
    return 0;
}

/// run_scene, with the summary written whatever the outcome (a batch runner reads the status).
int run_with_summary(const RunOptions& o) {
    RunSummary summary;
    summary.scene = o.scene.scene;
    const auto write = [&](const char* status, const std::string& message) {
        if (o.summary.empty()) return;
        summary.status = status, summary.message = message;
        write_summary(o.summary, summary);
    };
    try {
        const int code = run_scene(o, summary);
        write("ok", "");
        return code;
    } catch (const InputError& e) {
        write("input_error", e.what());
        throw;
    } catch (const NumericalError& e) {
        write("numerical_error", e.what());
        throw;
    }
}

}  // namespace

Command add_run_command(CLI::App& app) {
    auto o = std::make_shared<RunOptions>();
    CLI::App* cmd = app.add_subcommand("run", "Run a scene headless: ParaView series + metrics CSV");
    add_scene_options(*cmd, o->scene);
    cmd->add_option("--steps", o->scene.steps, "Override the scene's step count")->check(CLI::NonNegativeNumber);
    cmd->add_option("--output,-o", o->output, "Output directory (default: the scene's output.directory)");
    cmd->add_option("--record", o->record, "Record the tools' poses each step to DIR/<tool>.csv");
    cmd->add_option("--replay", o->replay, "Drive the tools from a session recorded with --record (bit-identical)");
    cmd->add_flag("--haptics", o->haptics, "Run the 1 kHz haptic loop beside the physics; report its rate and jitter");
    cmd->add_option("--summary", o->summary,
                    "Write the run's final figures, status and warnings to FILE as JSON (also when it fails)");
    cmd->add_flag("--no-output", o->no_output, "Write no series, metrics CSV, surfaces or picture (batch runs)");
    return {cmd, [o] { return run_with_summary(*o); }};
}

}  // namespace xcut
