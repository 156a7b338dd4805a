// xcut view SCENE: the live viewer (tools/viewer/viewer_app.h), when this build has it (XCUT_VIEWER).
#include "engine/error.h"
#include "tools/xcut_commands.h"
#ifdef XCUT_HAS_VIEWER
#include "tools/viewer/viewer_app.h"
#endif

namespace xcut {

Command add_view_command(CLI::App& app) {
    struct Options {
        SceneOptions scene;
        int width = 1280, height = 800;
        bool paused = false, panels = false, run_on = false;
        std::string record, input, screenshot, reference, bench_csv, timing_csv;
        double bench = 0.0, fps = 60.0;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("view", "Open a scene in a window: watch it, cut it with the mouse (docs/viewer.md)");
    add_scene_options(*cmd, o->scene);
    cmd->add_option("--steps", o->scene.steps, "Pause after this many steps (default: the scene's duration)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--run-on", o->run_on, "Do not pause at the scene's duration (play also goes on past it)");
    cmd->add_flag("--paused", o->paused, "Open paused (space plays)");
    cmd->add_option("--size", o->width, "Window width in pixels (height: 5/8 of it)")->check(CLI::Range(320, 8192));
    cmd->add_option("--record", o->record, "Record the session to DIR (xcut run SCENE --replay DIR replays it)");
    cmd->add_option("--input", o->input, "Play mouse and key events from FILE, one step a frame (docs/viewer.md)");
    cmd->add_option("--screenshot", o->screenshot, "Once the steps and events are done, save the 3D view as PNG and exit");
    cmd->add_option("--reference", o->reference, "With --screenshot: also the headless Embree render of the same state");
    cmd->add_flag("--panels", o->panels, "The screenshot shows the panels too");
    cmd->add_option("--bench", o->bench, "Measure the step rate with and without the window for S seconds each")
        ->check(CLI::PositiveNumber);
    CLI::Option* fps = cmd->add_option("--fps", o->fps, "Frame cap (default 60, 30 on software OpenGL; 0: none)")
                           ->check(CLI::NonNegativeNumber);
    cmd->add_option("--bench-csv", o->bench_csv, "Append the benchmark's row to FILE");
    cmd->add_option("--timing-csv", o->timing_csv,
                    "Keep every frame's and physics step's time; at the end print how evenly they came and append "
                    "the row to FILE");
    return {cmd, [o, fps]() -> int {
#ifdef XCUT_HAS_VIEWER
                viewer::ViewerOptions v;
                v.scene = o->scene.scene, v.overrides = o->scene.all_overrides(), v.threads = o->scene.threads;
                v.width = o->width, v.height = o->width * 5 / 8, v.steps = o->scene.steps, v.paused = o->paused;
                v.run_on = o->run_on;
                v.record = o->record, v.input = o->input, v.screenshot = o->screenshot, v.reference = o->reference;
                v.panels = o->panels, v.fps = o->fps, v.fps_given = fps->count() > 0;
                v.bench_seconds = o->bench, v.bench_csv = o->bench_csv, v.timing_csv = o->timing_csv;
                if (o->screenshot.empty() && !o->reference.empty())
                    throw InputError("xcut view", "--reference", "needs --screenshot");
                return viewer::run_viewer(v);
#else
                throw InputError("xcut view", "build", "this xcut was built without the viewer (XCUT_VIEWER=OFF, or "
                                 "GLFW, Dear ImGui or libepoxy missing: tools/install-deps.sh installs them)");
#endif
            }};
}

}  // namespace xcut
