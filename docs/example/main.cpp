// Loads a scene, steps it a few times with xcut's public API and prints the largest nodal
// displacement. Usage: xcut_example SCENE.json [STEPS]
#include <cstdio>
#include <cstdlib>

#include "engine/error.h"
#include "systems/pipeline.h"

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE.json [STEPS]\n", argv[0]);
        return 2;
    }
    const int steps = argc > 2 ? std::atoi(argv[2]) : 5;
    try {
        const xcut::Scene scene = xcut::load_scene(argv[1]);
        const auto sim = xcut::make_simulation(scene, /*with_output=*/false);
        for (int i = 0; i < steps; ++i) xcut::step_simulation(*sim);
        const xcut::Nodes& nodes = sim->world.nodes;
        double max_displacement = 0.0;
        for (int i = 0; i < sim->world.mesh_nodes; ++i)
            max_displacement = std::max(max_displacement, (nodes.position[i] - nodes.rest[i]).norm());
        std::printf("steps %d, nodes %d, max displacement %.6g m\n", steps, sim->world.mesh_nodes, max_displacement);
    } catch (const xcut::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    return 0;
}
