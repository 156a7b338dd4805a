// Scene JSON loader (load_scene). Lines "//set field.path=value" in the input (JSON comments, which
// the loader ignores) are also passed as --set overrides, so the override path is fuzzed too. A
// mesh file named inside the fuzzer's own folder (e.g. "." — a directory) is opened too
// (load_scene_mesh); one anywhere else is not, so an input cannot make the fuzzer read the disk.
#include <sstream>
#include <vector>

#include "engine/io/scene.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(xcut::fuzz::as_text(data, size));
    std::vector<std::string> overrides;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("//set ", 0) == 0) overrides.push_back(line.substr(6));
    const std::string path = xcut::fuzz::write_file("scene.json", text);
    xcut::fuzz::expect_clean([&] {
        const xcut::Scene scene = xcut::load_scene(path, overrides);
        const std::filesystem::path mesh = scene.mesh.file;
        if (!mesh.empty() && (mesh == xcut::fuzz::temp_dir() || mesh.parent_path() == xcut::fuzz::temp_dir()))
            xcut::load_scene_mesh(scene);
    });
    return 0;
}
