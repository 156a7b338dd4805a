#pragma once
// The conforming reference of docs/verification.md problem 5: the cut block (tools/studies/accuracy_problems.h)
// on a fine structured mesh whose element faces lie on the cut plane, nodes duplicated across the
// cut part of it (a conforming crack: no cutter involved). Its displacement at the sample points is
// cached as CSV, keyed by the problem's parameters, and recomputed when the file is missing.
#include <string>
#include <vector>

#include "tools/studies/accuracy_problems.h"
#include "engine/mesh_data.h"

namespace xcut {

/// Kuhn tetrahedra on a tensor grid of cell size about L / n: x = cut_x and z = H - d are grid
/// planes. Every node on the plane x = cut_x with z > H - d (the cut part, top face included) is
/// duplicated, and the elements beyond the plane (x > cut_x) use the copies; nodes on the crack
/// front z = H - d stay shared.
MeshData generate_cracked_block(const CutBlockSpec& spec, int n);

struct ReferenceField {
    std::vector<Vec3> displacement;  ///< at cut_block_samples(spec) [m]
    int dofs = 0;                    ///< 3 x nodes of the reference mesh
    double solve_s = 0.0;            ///< wall time of the solve when it was computed [s]
    bool from_cache = false;
    std::string path;                ///< the cache file
};
/// The reference solution with n cells along L: read from `cache_dir`/cut_block_ref_<key>.csv when
/// it exists and its header matches the parameters, else solved (static equilibrium, the suite's
/// tolerances) and written there.
ReferenceField cut_block_reference(const CutBlockSpec& spec, int n, const std::string& cache_dir);

}  // namespace xcut
