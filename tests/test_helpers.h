#pragma once
// Small builders shared by the tests.
#include "engine/generators.h"
#include "engine/setup.h"
#include "engine/world.h"

namespace xcut::testing {

inline World world_from_mesh(const MeshData& mesh, const Material& material = Material{}) {
    World world;
    world.materials.list = {material};
    build_bodies(world, mesh);
    return world;
}

inline GridSpec grid(const Eigen::Vector3d& size, const Eigen::Vector3i& cells, double jitter = 0.0,
                     uint64_t seed = 1) {
    GridSpec g;
    g.size = size;
    g.cells = cells;
    g.jitter = jitter;
    g.seed = seed;
    return g;
}

}  // namespace xcut::testing
