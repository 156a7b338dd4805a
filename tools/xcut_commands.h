#pragma once
// The subcommands of the `xcut` front end, one file each beside tools/xcut.cpp. Each adds itself
// to the command line and returns its subcommand with what to run when it is the one parsed; the
// front end turns an InputError into exit 2 and any other exception into exit 1.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "engine/io/render.h"

namespace xcut {

struct Scene;
struct World;

struct Command {
    CLI::App* app = nullptr;    ///< the subcommand, owned by the front end's CLI::App
    std::function<int()> run;  ///< its exit code
};

Command add_run_command(CLI::App& app);      ///< xcut run: step a scene headless (xcut_run.cpp)
Command add_render_command(CLI::App& app);   ///< xcut render: run, then a PNG (xcut_render.cpp)
Command add_bench_command(CLI::App& app);    ///< xcut bench --suite ... (xcut_bench.cpp)
Command add_stress_command(CLI::App& app);   ///< xcut stress (xcut_stress.cpp)
Command add_compare_command(CLI::App& app);  ///< xcut compare SCENE (xcut_compare.cpp)
Command add_schedule_command(CLI::App& app); ///< xcut schedule SCENE [--dataflow] (xcut_schedule.cpp)
Command add_mesh_command(CLI::App& app);     ///< xcut mesh FILE: what a mesh file reads as (xcut_mesh.cpp)
Command add_view_command(CLI::App& app);     ///< xcut view SCENE: the live viewer (xcut_view.cpp)

/// The options every scene-running subcommand shares.
struct SceneOptions {
    std::string scene;
    int threads = 2;
    int steps = -1;
    std::vector<std::string> overrides;  ///< --set field.path=value
    bool quiet = false;
    std::string cutter;                  ///< --cutter: sets cutter.type
    std::vector<std::string> allow;      ///< --allow: plausibility checks silenced (the scene's "allow")
    /// The overrides with --cutter folded in.
    std::vector<std::string> all_overrides() const;
};

/// Adds the scene positional and --threads, --set, --quiet, --cutter to `cmd`.
void add_scene_options(CLI::App& cmd, SceneOptions& o);

/// Renders the world's visual surface as the scene's camera sees it (automatic: framed) to `png`.
void render_scene_png(const Scene& scene, const World& world, const std::string& png,
                      const RenderOptions& options = {});

}  // namespace xcut
