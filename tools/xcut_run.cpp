// xcut run SCENE: step a scene headless; ParaView series, metrics CSV and a PNG of the surface.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include "engine/io/scene_checks.h"
#include "engine/parallel.h"
#include "systems/cut/enrichment_system.h"
#include "systems/pipeline.h"
#include "tools/xcut_commands.h"

namespace xcut {
namespace {

struct RunOptions {
    SceneOptions scene;
    std::string output;
    std::string record, replay;  ///< session directories (engine/devices/device.h)
    bool haptics = false;        ///< run the 1 kHz haptic loop beside the physics
};

void print_result(const World& w, int steps, double secs) {
    const StepMetrics& m = w.metrics.current;
    const Metrics& all = w.metrics;
    if (all.refactored_steps > 0 || all.substepped_steps > 0)
        fmt::print(stderr, "warning: to reach the CG tolerance, of {} steps {} needed a renewed factor and {} substeps "
                           "(up to {} each); solve_flag and substeps in the metrics CSV say which\n",
                   steps, all.refactored_steps, all.substepped_steps, all.max_substeps);
    double max_disp = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) max_disp = std::max(max_disp, (w.nodes.position[i] - w.nodes.rest[i]).norm());
    fmt::print("done: t = {:.4g} s in {:.3f} s wall ({:.1f} steps/s); free DOFs {}; last step {} CG iterations; "
               "max displacement {:.4g} m; kinetic {:.4g} J, elastic {:.4g} J\n",
               w.time, secs, steps / std::max(secs, 1e-9), m.dofs, m.cg_iterations, max_disp, m.kinetic_energy,
               m.elastic_energy);
    if (w.cuts.count() > 0) {
        double opening = 0.0;
        for (int j = 0; j < w.mesh_nodes; ++j) opening = std::max(opening, enriched_displacement(w, j).norm());
        fmt::print("cut: {} elements split, {} enriched DOF nodes ({} held by the crack front), max opening |a_j| {:.4g} m\n",
                   w.cuts.count(), w.enriched.count(),
                   std::count(w.enriched.front_fixed.begin(), w.enriched.front_fixed.end(), 1), opening);
    }
    if (w.snap.elements_split > 0)
        fmt::print("cut (snap): {} elements split, {} nodes snapped (largest move {:.3g} m), {} edge points, {} copies\n",
                   w.snap.elements_split, w.snap.snaps, w.snap.max_snap_distance, w.snap.points, w.snap.copies);
}

int run_scene(const RunOptions& o) {
    set_thread_count(o.scene.threads);
    std::vector<std::string> overrides = o.scene.all_overrides();
    if (!o.replay.empty()) {  // the session's overrides (its command line's, the viewer's tools) last: they win
        std::vector<std::string> session = read_session_overrides(o.replay);
        overrides.insert(overrides.end(), session.begin(), session.end());
    }
    Scene scene = load_scene(o.scene.scene, overrides);
    if (!o.output.empty()) scene.output.directory = o.output;
    // A replay runs to the end of its recording (a session recorded past the scene's duration
    // holds what was done there); --steps still decides when given.
    const int recorded = o.replay.empty() ? 0 : static_cast<int>(read_session_steps(o.replay).size());
    const int steps = o.scene.steps >= 0 ? o.scene.steps : recorded > 0 ? recorded : scene.steps;
    if (o.scene.steps < 0 && recorded > 0 && recorded != scene.steps)
        fmt::print("replay: {} steps, as recorded (the scene says {})\n", recorded, scene.steps);
    scene.steps = steps;  // what the run takes: the output's bound is checked against it
    auto sim = make_simulation(scene, true, o.replay);
    if (!o.record.empty()) sim->recorder = std::make_unique<SessionRecorder>(sim->world, o.record, SessionInfo{o.scene.scene, overrides});
    std::unique_ptr<HapticLoop> haptics = start_haptics(*sim, o.haptics);
    sim->world.verbose = true;
    const World& w = sim->world;
    const char* wait = std::getenv("OMP_WAIT_POLICY");
    fmt::print("scene {} ({}): {} nodes, {} {}, {} threads (OpenMP wait {}), dt {} s ({}), {} steps\n", scene.name,
               o.scene.scene, w.nodes.count(), w.elements.count(), w.elements.dim == 3 ? "tetrahedra" : "triangles",
               thread_count(), wait ? wait : "active", w.solver.dt, w.solver.realtime ? "real-time" : "fixed", steps);
    for (const std::string& note : w.mesh_notes) fmt::print(stderr, "warning: {}\n", note);
    for (const std::string& note : plausibility_warnings(scene, w, steps)) fmt::print(stderr, "warning: {}\n", note);
    fmt::print("{}", sim->scheduler.describe(w));
    if (w.linear.load_setup_ms > 0.0)
        fmt::print("linear solver: {} built at load in {:.0f} ms\n",
                   w.linear.method == "amg" ? "the multigrid hierarchy" : "the Cholesky factor", w.linear.load_setup_ms);
    const auto t0 = std::chrono::steady_clock::now();
    run_simulation(*sim, steps, !o.scene.quiet);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (haptics) {
        haptics->stop();
        const HapticStats h = haptics->stats();
        fmt::print("haptics: {} ticks in {:.2f} s ({:.0f} Hz, target 1000); period p50 {:.3f} ms, p99 {:.3f} ms, max {:.3f} ms\n",
                   h.ticks, h.seconds, h.rate_hz, h.period_p50_ms, h.period_p99_ms, h.period_max_ms);
    }
    if (!o.record.empty()) fmt::print("session recorded: {}/<tool>.csv\n", o.record);
    print_result(w, steps, secs);
    for (const std::string& note : end_of_run_notes(w)) fmt::print(stderr, "warning: {}\n", note);
    if (sim->output && w.visual.vertex_count() > 0) {
        const std::string png = sim->output->directory() + "/" + scene.name + ".png";
        render_scene_png(scene, w, png);
        fmt::print("render: {}\n", png);
    }
    if (sim->output) fmt::print("output: {}/{}.pvd and {}_metrics.csv\n", sim->output->directory(), scene.name, scene.name);
    return 0;
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
    return {cmd, [o] { return run_scene(*o); }};
}

}  // namespace xcut
