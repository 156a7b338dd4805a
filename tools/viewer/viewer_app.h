#pragma once
// `xcut view SCENE`: a GLFW window with OpenGL 3.3 core and Dear ImGui panels over a simulation that
// steps on a thread of its own (tools/viewer/physics_thread.h). Cut with the mouse, drive a probe
// with the keys, take over the scene's tools; --record saves the session for `xcut run --replay`.
// docs/viewer.md tells the controls.
#include <string>
#include <vector>

namespace xcut::viewer {

struct ViewerOptions {
    std::string scene;
    std::vector<std::string> overrides;  ///< --set, --cutter
    int threads = 2;
    int width = 1280, height = 800;      ///< window size [pixels]
    int steps = -1;                      ///< pause after this many steps (< 0: the scene's duration)
    bool run_on = false;                 ///< --run-on: do not pause at the scene's duration
    bool paused = false;                 ///< start paused
    std::string record;                  ///< session directory
    std::string input;                   ///< scripted input (tools/viewer/scripted_input.h)
    std::string screenshot;              ///< once idle: save the 3D view (no panels) and exit
    std::string reference;               ///< with --screenshot: also the headless render of that snapshot
    bool panels = false;                 ///< the screenshot shows the panels too
    double fps = 60.0;                   ///< frame cap [1/s]; 0: none; halved on software OpenGL
    bool fps_given = false;              ///< the user set the cap: keep it as given
    double bench_seconds = 0.0;          ///< > 0: measure step rate with and without the window
    std::string bench_csv;               ///< where the benchmark writes its row
    std::string timing_csv;              ///< frame and physics update intervals: their row goes here
};

/// Runs the viewer; the process's exit code (0, or 3 when the physics failed).
int run_viewer(const ViewerOptions& options);

}  // namespace xcut::viewer
