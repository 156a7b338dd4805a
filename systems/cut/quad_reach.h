#pragma once
// Which mesh elements a blade's swept quads can reach (systems/cut/cut_system.cpp): the search for
// the elements a quad may cross, from the blade's front outward (paper §3.3: the collision quad).
#include <array>
#include <utility>
#include <vector>

#include "components/cut_state.h"
#include "engine/world.h"

namespace xcut {

/// Where the quads of one update can reach (the edge's sweep, the blade's face): their box, and the
/// planes of their triangles (a non-planar quad is two triangles; an element a quad crosses
/// straddles one of their planes), each as a point and a normal.
struct QuadReach {
    Vec3 lo, hi;
    std::vector<std::pair<Vec3, Vec3>> planes;
};

/// The reach of `quads` (each with its triangles' normals), its box grown by rounding only.
QuadReach quad_reach(const std::vector<const CutQuad*>& quads, const std::vector<std::array<Vec3, 2>>& normals);

/// Elements sharing a vertex with `seeds`, `depth` levels deep (seeds included), and beyond that
/// every element connected to them through elements the swept quad may reach: the depth is sized by
/// the mean edge, which on a graded mesh is many of its small elements, so the quad's own extent
/// decides where the search ends. Sorted.
std::vector<int> neighbourhood(const World& world, const std::vector<int>& seeds, int depth, const QuadReach& quad);

}  // namespace xcut
