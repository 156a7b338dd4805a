// xcut render SCENE: run a scene, then ray-cast its visual surface to a PNG (Embree).
#include <fmt/format.h>

#include "engine/io/render.h"
#include "engine/parallel.h"
#include "systems/pipeline.h"
#include "tools/xcut_commands.h"

namespace xcut {

void render_scene_png(const Scene& scene, const World& w, const std::string& png, const RenderOptions& options) {
    const Camera cam = scene.camera.automatic ? frame_world(w, scene.camera.width, scene.camera.height, options)
                                              : scene.camera;
    write_png(render_world(w, cam, options), png);
}

Command add_render_command(CLI::App& app) {
    struct Options {
        SceneOptions scene;
        std::string png;
        RenderOptions render;
        bool no_tools = false, no_scale_bar = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("render", "Run a scene and render its visual surface to a PNG (Embree)");
    add_scene_options(*cmd, o->scene);
    cmd->add_option("--steps", o->scene.steps, "Steps to run before rendering (default: the scene's)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--png,-o", o->png, "PNG to write (default: <scene name>.png)");
    cmd->add_option("--field", o->render.field, "Colour the surface by a field, with a colour bar")
        ->check(CLI::IsMember({"von_mises", "displacement"}));
    cmd->add_flag("--no-tools", o->no_tools, "Leave the tools out of the picture");
    cmd->add_flag("--no-scale-bar", o->no_scale_bar, "Leave the scale bar out");
    return {cmd, [o] {
                set_thread_count(o->scene.threads);
                Scene scene = load_scene(o->scene.scene, o->scene.all_overrides());
                if (scene.visual_subdivisions < 0) scene.visual_subdivisions = 0;
                auto sim = make_simulation(scene, /*with_output=*/false);
                run_simulation(*sim, o->scene.steps >= 0 ? o->scene.steps : scene.steps, !o->scene.quiet);
                const std::string out = o->png.empty() ? scene.name + ".png" : o->png;
                o->render.tools = !o->no_tools, o->render.scale_bar = !o->no_scale_bar;
                render_scene_png(scene, sim->world, out, o->render);
                fmt::print("render: {} (t = {:.4g} s, {} triangles)\n", out, sim->world.time,
                           sim->world.visual.triangles.size());
                return 0;
            }};
}

}  // namespace xcut
