// OBJ/STL reader: closed surface checks, TetGen's tetrahedralization, mesh validation. The input is
// an STL when it starts with "solid" or holds a NUL byte (binary STL), else an OBJ.
#include <cstring>

#include "engine/io/mesh_io.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text = xcut::fuzz::as_text(data, size);
    const bool stl = text.rfind("solid", 0) == 0 || text.find('\0') != std::string_view::npos;
    const std::string path = xcut::fuzz::write_file(stl ? "surface.stl" : "surface.obj", text);
    xcut::fuzz::expect_clean([&] { xcut::read_mesh_file(path, 0.0); });
    return 0;
}
