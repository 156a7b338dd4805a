#pragma once
// Opening an input file (scene, mesh, trajectory, session) the one way every reader does, so a
// missing file, a directory or an unreadable file is said as such, naming the path and the field
// that named it, before any reader tries to parse it.
#include <cstddef>
#include <string>

namespace xcut {

/// The whole content of `path` (binary-safe). Throws InputError(path, field, ...) when it does not
/// exist, is a directory or another non-regular file (a device, a pipe), or cannot be read; `kind` says what was expected ("mesh", "scene", ...).
/// A file larger than `max_bytes` is refused before it is read, naming the bound.
std::string read_input_file(const std::string& path, const std::string& field, const std::string& kind,
                            size_t max_bytes = size_t{2} << 30);

}  // namespace xcut
