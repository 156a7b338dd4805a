#pragma once
// Shared by the libFuzzer targets (docs/fuzzing.md): the input goes to a file in a per-process
// temporary folder (the readers take paths), and an InputError is the expected way to reject it.
// Anything else escaping the reader (another exception, a crash, a sanitizer report, a hang) is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "engine/error.h"
#include "engine/io/mesh_io.h"

namespace xcut::fuzz {

/// A surface whose quality mesh needs more than 20,000 added points is refused (an InputError)
/// instead of meshed: a thin feature made TetGen add 180,000 points, 13 s per input (a fuzz timeout).
inline const bool kMesherLimited = (set_mesher_point_limit(20000), true);

inline const std::filesystem::path& temp_dir() {
    static const std::filesystem::path dir = [] {
        const auto d = std::filesystem::temp_directory_path() / ("xcut_fuzz_" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

/// Writes `bytes` to temp_dir()/name and returns the path.
inline std::string write_file(const std::string& name, std::string_view bytes) {
    const std::string path = (temp_dir() / name).string();
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
}

/// Runs `read`; an InputError is a clean rejection.
template <class F>
void expect_clean(F&& read) {
    try {
        read();
    } catch (const InputError&) {
    }
}

inline std::string_view as_text(const uint8_t* data, size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

}  // namespace xcut::fuzz
