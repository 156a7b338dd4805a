// Recorded tool trajectory reader (read_trajectory_csv).
#include "engine/io/scene.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = xcut::fuzz::write_file("trajectory.csv", xcut::fuzz::as_text(data, size));
    xcut::fuzz::expect_clean([&] { xcut::read_trajectory_csv(path); });
    return 0;
}
