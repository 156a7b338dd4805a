#pragma once
// The surface's per-vertex and per-triangle arrays kept in step (components/surface_mesh.h), for the
// overlays laid over it after a cut and taken off before the next (the crack tips' opening,
// systems/surface/surface_tips.h; the copies where wounds touch, systems/surface/surface_manifold.h).
#include <cstdint>
#include <vector>

#include "components/surface_mesh.h"

namespace xcut {

/// Keeps the first `count` vertices (every per-vertex array).
inline void keep_vertices(SurfaceMesh& s, size_t count) {
    s.position.resize(count), s.element.resize(count), s.bary.resize(count), s.side.resize(count);
}

/// Drops the triangles flagged in `drop` (those past its end stay), the others kept in order (every
/// per-triangle array).
inline void drop_triangles(SurfaceMesh& s, const std::vector<uint8_t>& drop) {
    size_t kept = 0;
    for (size_t t = 0; t < s.triangles.size(); ++t) {
        if (t < drop.size() && drop[t]) continue;
        s.triangles[kept] = s.triangles[t], s.triangle_owner[kept] = s.triangle_owner[t], s.cut_face[kept] = s.cut_face[t];
        ++kept;
    }
    s.triangles.resize(kept), s.triangle_owner.resize(kept), s.cut_face.resize(kept);
}

}  // namespace xcut
