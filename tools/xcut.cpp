// xcut: the command-line front end. Each subcommand is a file of its own beside this one
// (xcut_run.cpp, xcut_render.cpp, xcut_bench.cpp, xcut_stress.cpp, xcut_compare.cpp,
// xcut_schedule.cpp).
#include <fmt/format.h>

#include <exception>
#include <string>

#ifdef XCUT_HAS_IGTL
#include "engine/devices/igtl/igtl_device.h"
#endif
#include "engine/error.h"
#include "engine/startup_environment.h"
#include "tools/xcut_commands.h"

namespace xcut {

std::vector<std::string> SceneOptions::all_overrides() const {
    std::vector<std::string> all = overrides;
    if (!cutter.empty()) all.push_back("cutter.type=\"" + cutter + "\"");
    for (const std::string& check : allow) all.push_back("allow+=\"" + check + "\"");
    return all;
}

void add_scene_options(CLI::App& cmd, SceneOptions& o) {
    cmd.add_option("scene", o.scene, "Scene file (JSON, see docs/scene-format.md)")->required();
    cmd.add_option("--threads,-j", o.threads, "OpenMP threads (results are identical for any count)")
        ->check(CLI::Range(1, 256));
    cmd.add_option("--set", o.overrides, "Override a scene field: field.path=value (JSON value)");
    cmd.add_flag("--quiet,-q", o.quiet, "No progress bar");
    cmd.add_option("--cutter", o.cutter, "Cutter: xfem (default) or snap (snapping and subdivision)")
        ->check(CLI::IsMember({"xfem", "snap"}));
    cmd.add_option("--allow", o.allow,
                   "Silence a plausibility warning: units, young, density, poisson, tool_reach, dt (repeatable)");
}

}  // namespace xcut

int main(int argc, char** argv) {
    xcut::ensure_startup_environment(argv);
#ifdef XCUT_HAS_IGTL
    xcut::register_igtl_device();  // tools with "device": {"type": "igtl"}
#endif
    CLI::App app{"xcut: real-time cutting of soft tissue with the corotational XFEM"};
    app.require_subcommand(1);
    const std::vector<xcut::Command> commands = {
        xcut::add_run_command(app),    xcut::add_render_command(app),  xcut::add_bench_command(app),
        xcut::add_stress_command(app), xcut::add_compare_command(app), xcut::add_schedule_command(app),
        xcut::add_mesh_command(app),   xcut::add_view_command(app),
    };
    CLI11_PARSE(app, argc, argv);
    try {
        for (const xcut::Command& c : commands)
            if (c.app->parsed()) return c.run();
    } catch (const xcut::InputError& e) {
        fmt::print(stderr, "error: {}\n", e.what());
        return 2;
    } catch (const CLI::Error& e) {  // an option the command refuses once it knows the rest (xcut bench)
        fmt::print(stderr, "error: {}\n", e.what());
        return 2;
    } catch (const xcut::NumericalError& e) {
        fmt::print(stderr, "error: the simulation failed: {}\n", e.what());
        return 3;
    } catch (const std::exception& e) {
        fmt::print(stderr, "error: {}\n", e.what());
        return 1;
    }
    return 0;
}
