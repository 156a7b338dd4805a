// xcut render SCENE: run a scene, then ray-cast its visual surface to a PNG (Embree).
#include <fmt/format.h>

#include "engine/io/render.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "tools/xcut_commands.h"

namespace xcut {

void render_scene_png(const Scene& scene, const World& w, const std::string& png) {
    const Camera cam = scene.camera.automatic ? frame_surface(w.visual, scene.camera.width, scene.camera.height)
                                              : scene.camera;
    write_png(render_surface(w.visual, cam), png);
}

Command add_render_command(CLI::App& app) {
    struct Options {
        SceneOptions scene;
        std::string png;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("render", "Run a scene and render its visual surface to a PNG (Embree)");
    add_scene_options(*cmd, o->scene);
    cmd->add_option("--steps", o->scene.steps, "Steps to run before rendering (default: the scene's)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--png,-o", o->png, "PNG to write (default: <scene name>.png)");
    return {cmd, [o] {
                set_thread_count(o->scene.threads);
                Scene scene = load_scene(o->scene.scene, o->scene.all_overrides());
                if (scene.visual_subdivisions < 0) scene.visual_subdivisions = 0;
                auto sim = make_simulation(scene, /*with_output=*/false);
                run_simulation(*sim, o->scene.steps >= 0 ? o->scene.steps : scene.steps, !o->scene.quiet);
                const std::string out = o->png.empty() ? scene.name + ".png" : o->png;
                render_scene_png(scene, sim->world, out);
                fmt::print("render: {} (t = {:.4g} s, {} triangles)\n", out, sim->world.time,
                           sim->world.visual.triangles.size());
                return 0;
            }};
}

}  // namespace xcut
