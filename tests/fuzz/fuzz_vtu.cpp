// VTK XML reader (.vtu: ascii, base64 binary, appended raw/base64, zlib) and the mesh validation
// behind it.
#include "engine/io/mesh_io.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = xcut::fuzz::write_file("mesh.vtu", xcut::fuzz::as_text(data, size));
    xcut::fuzz::expect_clean([&] { xcut::read_mesh_file(path, 0.0); });
    return 0;
}
