// TetGen reader (.node + .ele) and the mesh validation behind it. The input holds both files: the
// .node text, then a line "#ele" (a comment to TetGen), then the .ele text. Without the marker both
// files get the whole input.
#include "engine/io/mesh_io.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text = xcut::fuzz::as_text(data, size);
    const size_t cut = text.find("#ele");
    const std::string_view node = cut == std::string_view::npos ? text : text.substr(0, cut);
    const std::string_view ele = cut == std::string_view::npos ? text : text.substr(cut);
    xcut::fuzz::write_file("mesh.node", node);
    const std::string path = xcut::fuzz::write_file("mesh.ele", ele);
    xcut::fuzz::expect_clean([&] { xcut::read_mesh_file(path, 0.0); });
    return 0;
}
