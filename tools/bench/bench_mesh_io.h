#pragma once
// `xcut bench --suite mesh_io`: how long the mesh readers take on one large mesh written by the real
// programs (gmsh: binary Gmsh 4.1 and 2.2; meshio and VTK's writer: VTU inline zlib, appended raw and
// appended zlib; VTK: legacy binary). The mesh is a box meshed by gmsh to about 200,000 tets (--tiny:
// about 20,000). A benchmark: it prints figures and writes CSV (results/bench_mesh_io.csv; a --tiny
// run writes results/bench_mesh_io_quick.csv, never the record). Needs gmsh, and python3 with meshio
// and VTK (tools/install-deps.sh); says so and exits 2 without them.
#include <string>

namespace xcut {

struct MeshIoBenchOptions {
    bool tiny = false;
    std::string csv;  ///< default: results/bench_mesh_io.csv, or ..._quick.csv when tiny
    int repeats = 3;  ///< reads per file; the fastest is reported
};

int mesh_io_bench_command(const MeshIoBenchOptions& options);

}  // namespace xcut
