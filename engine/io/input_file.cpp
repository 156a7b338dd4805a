#include "engine/io/input_file.h"

#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>

#include "engine/error.h"

namespace xcut {

std::string read_input_file(const std::string& path, const std::string& field, const std::string& kind,
                            size_t max_bytes) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) throw InputError(path, field, "no such " + kind + " file");
    if (fs::is_directory(status)) throw InputError(path, field, "is a directory, not a " + kind + " file");
    // A device or a pipe (/dev/zero, a FIFO) could be read forever: only regular files are inputs.
    if (!fs::is_regular_file(status)) throw InputError(path, field, "is not a regular file (a device or a pipe?)");
    const auto bytes = fs::file_size(path, ec);
    if (!ec && bytes > max_bytes)
        throw InputError(path, field, fmt::format("is {} bytes, above the {} bytes a {} file may have (the limit)", bytes,
                                                  max_bytes, kind));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, field, "cannot open the " + kind + " file (permissions?)");
    std::stringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw InputError(path, field, "cannot read the " + kind + " file");
    return ss.str();
}

}  // namespace xcut
