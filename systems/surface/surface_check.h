#pragma once
// Whether a surface is what the cut promises (docs/xfem.md, Several cuts per element): a 3D body's
// surface closed and oriented (each edge used once each way), a 2D body's sheet without overlaps,
// and no triangle without area. The stress suite holds these over random trajectories; a run
// checks its own surfaces after every step that cuts them and says so at its end, rather than
// drawing a hole nobody is told about (cutting again in 3D, `cutter.recut`, still leaves open edges
// in a few percent of random four-blade runs: docs/BENCHMARKS.md).
#include "components/surface_mesh.h"

namespace xcut {

/// A surface's defects. `open`: edges used a different number of times in its two directions (a
/// gap; 3D only: a 2D sheet is open at its borders and along a cut by design). `pinched`: edges
/// used equally often each way but more than once (closed, not 2-manifold: two wounds meeting
/// along a line); in 2D, a directed edge used more than once (two triangles overlapping there).
/// `zero_area`: triangles without area (zero_area_triangles, systems/surface/surface_cut.h).
struct SurfaceDefects {
    int open = 0, pinched = 0, zero_area = 0;
    int total() const { return open + pinched + zero_area; }
};

/// The defects of `surface` as it is (`closed`: a 3D body's surface; else a 2D sheet). One pass
/// over its triangles' directed edges, sorted: O(T log T) for T triangles.
SurfaceDefects surface_defects(const SurfaceMesh& surface, bool closed);

/// Records `surface`'s defects now in it (SurfaceMesh::open_edges ...; defects_since the first
/// time at `time` [s] they are seen, -1 again once there are none): after a step that cut it.
void note_defects(SurfaceMesh& surface, bool closed, double time);

}  // namespace xcut
