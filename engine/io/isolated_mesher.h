#pragma once
// Runs a mesher that may abort the process (TetGen 1.5 asserts inside its geometric predicates on
// some near-degenerate or self-intersecting surfaces, whatever is checked before) in a forked child:
// the child sends back the mesh or the InputError it threw; a child killed by a signal becomes an
// InputError naming the file, never the end of the run. POSIX fork and a pipe; the child runs no
// OpenMP and leaves with _exit. Internal to engine/io.
#include <functional>
#include <string>

#include "engine/mesh_data.h"

namespace xcut {

/// `mesh()`'s points and cells (its other fields are not carried), made in a child process.
MeshData run_isolated_mesher(const std::string& path, const std::function<MeshData()>& mesh);

}  // namespace xcut
