#pragma once
// Embree BVH over the bounding boxes of mesh elements at their current positions, for the cut's
// first-contact search: which elements can the blade's swept quad touch. Embree works in single
// precision; boxes are padded by a relative 1e-5 so no candidate is lost to rounding, and the exact
// decision is made in double afterwards.
#include <memory>
#include <vector>

#include "components/elements.h"
#include "components/nodes.h"

namespace xcut {

/// The mesh a BVH is built over: elements [0, mesh_elements) of `elements`, whose nodes
/// [0, mesh_nodes) are at `position` [m].
struct MeshView {
    const Elements* elements = nullptr;
    const std::vector<Vec3>* position = nullptr;
    int mesh_elements = 0, mesh_nodes = 0;
};

class ElementBvh {
public:
    ElementBvh();
    ~ElementBvh();
    ElementBvh(const ElementBvh&) = delete;
    ElementBvh& operator=(const ElementBvh&) = delete;

    /// (Re)builds over the mesh elements (not the virtual ones) at their positions, each box grown
    /// by `margin` [m] so the tree stays valid while no node moves further.
    void build(const MeshView& mesh, double margin = 0.0);
    /// Rebuilds only if never built or a node moved more than the margin since the last build:
    /// a deforming body rarely needs a new tree. Returns true if it rebuilt.
    bool ensure(const MeshView& mesh, double margin);
    /// Appends to `out` every element whose box meets the ball (centre, radius [m]).
    void query_ball(const Vec3& centre, double radius, std::vector<int>& out) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace xcut
