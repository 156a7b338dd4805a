// xcut schedule SCENE: the systems a scene runs and the ones it skips, without stepping it; with
// --dataflow, every system of the pipeline with the components it reads and writes (the table and
// picture of docs/architecture.md, generated from the scheduler's own declarations).
#include <fmt/format.h>

#include "systems/pipeline.h"
#include "tools/xcut_commands.h"

namespace xcut {

Command add_schedule_command(CLI::App& app) {
    struct Options {
        SceneOptions scene;
        bool dataflow = false;
    };
    auto o = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand("schedule", "Print the systems a scene runs and skips, without stepping it");
    add_scene_options(*cmd, o->scene);
    cmd->add_flag("--dataflow", o->dataflow,
                  "Every system in pipeline order with the components it reads and writes (Markdown + Mermaid)");
    return {cmd, [o] {
                const Scene scene = load_scene(o->scene.scene, o->scene.all_overrides());
                const auto sim = make_simulation(scene, /*with_output=*/false);
                fmt::print("{}", o->dataflow ? sim->scheduler.dataflow_markdown() : sim->scheduler.describe(sim->world));
                return 0;
            }};
}

}  // namespace xcut
