#pragma once
// Each mesh node's side of a quad's triangles, computed once per node and quad for the cut's edge
// tests (systems/cut/cut_system.cpp).
#include <array>
#include <cstdint>
#include <vector>

#include "engine/world.h"
#include "systems/kernels/intersection.h"

namespace xcut {

/// orient3d(a, b, c, x) of mesh node x against triangle abc of each quad (triangles (0, 1, 2) and
/// (0, 2, 3) of its corners, as edge_crossing takes them), computed on the node's first use in a
/// quad and kept for the quad's other edges: a quad's candidates share their nodes (a tetrahedron's
/// node belongs to about 20 of them), and these products, six per edge end, were 80 % of a quad's
/// time at 53k tets. The same expression on the same points as segment_triangle's own: the same
/// bits. Used by one thread at a time (one per process_cut_quad call).
class NodeSides {
public:
    /// Starts a quad: every node's value is computed anew on its first use.
    void begin(const World& w, const std::vector<const CutQuad*>& quads) {
        w_ = &w, quads_ = &quads;
        if (stamp_.size() != w.nodes.position.size() || ++epoch_ == 0)
            stamp_.assign(w.nodes.position.size(), 0), epoch_ = 1;
        if (side_.size() != stamp_.size()) side_.resize(stamp_.size());
    }
    /// Node j's orientation against triangle `tri` of quad k (k < 2).
    double at(int j, int k, int tri) {
        if (stamp_[j] != epoch_) {
            stamp_[j] = epoch_;
            const Vec3& x = w_->nodes.position[j];
            for (size_t q = 0; q < quads_->size() && q < 2; ++q) {
                const auto& c = (*quads_)[q]->corner;
                side_[j][2 * q] = orient3d(c[0], c[1], c[2], x);
                side_[j][2 * q + 1] = orient3d(c[0], c[2], c[3], x);
            }
        }
        return side_[j][2 * k + tri];
    }

private:
    const World* w_ = nullptr;
    const std::vector<const CutQuad*>* quads_ = nullptr;
    std::vector<uint32_t> stamp_;
    std::vector<std::array<double, 4>> side_;
    uint32_t epoch_ = 0;
};

}  // namespace xcut
