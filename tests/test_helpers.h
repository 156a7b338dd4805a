#pragma once
// Small builders shared by the tests.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <random>

#include <Eigen/Geometry>
#include <filesystem>
#include <string>

#include "engine/fnv_hash.h"
#include "engine/io/generators.h"
#include "engine/setup.h"
#include "engine/world.h"
#include "systems/cut/enrichment_system.h"
#include "systems/force_system.h"
#include "systems/cut/scripted_cut_system.h"
#include "systems/pipeline.h"
#include "systems/solver/solver_system.h"

namespace xcut::testing {

/// Whether this build runs under AddressSanitizer (the CI's sanitizer stage, about 40x slower on
/// numerical loops): randomized suites run fewer cases there, the release build runs them all.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kInstrumented = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kInstrumented = true;
#else
inline constexpr bool kInstrumented = false;
#endif
#else
inline constexpr bool kInstrumented = false;
#endif

/// FNV-1a over every DOF node's position and velocity (and the visual vertices when asked): two runs
/// that should agree bit for bit have the same hash.
inline uint64_t state_hash(const World& w, bool with_visual = false) {
    Hasher h;
    h.all(w.nodes.position, w.nodes.velocity);
    if (with_visual) h.add(w.visual.position);
    return h.h;
}

/// Runs a shell command line; its exit code (-1 if it did not exit), stdout and stderr in `out`.
inline int run_command(const std::string& cmd, std::string& out) {
    std::array<char, 4096> buf;
    FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
    out.clear();
    if (!p) return -1;
    while (size_t n = std::fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
    const int status = ::pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// A fresh folder under the system's temporary directory, unique to this process and `tag`.
inline std::filesystem::path temp_dir(const std::string& tag) {
    const auto d = std::filesystem::temp_directory_path() / ("xcut_" + std::to_string(::getpid()) + "_" + tag);
    std::filesystem::create_directories(d);
    return d;
}

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

/// A jittered, deformed body with its left face held: rotations and forces as the ForceSystem
/// leaves them.
inline World deformed(bool plate, const Eigen::Vector3i& cells = Eigen::Vector3i(6, 4, 2)) {
    World w = world_from_mesh(plate ? generate_plate(grid({0.03, 0.02, 0}, {6, 4, 1}, 0.2))
                                    : generate_box(grid({0.03, 0.02, 0.01}, {cells.x(), cells.y(), cells.z()}, 0.2)));
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    apply_constraints(w);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1e-3, 1e-3);
    for (int i = 0; i < w.nodes.count(); ++i) {
        const Vec3 d(u(rng), u(rng), plate ? 0.0 : u(rng));
        w.nodes.position[i] += d;
    }
    update_rotations(w);
    compute_forces(w);
    return w;
}

/// One step of the pipeline without a scheduler: pending cuts, forces, implicit Euler.
inline void step_world(World& world) {
    apply_cut_events(world);
    update_rotations(world);
    compute_forces(world);
    implicit_euler_step(world, xcut_step_terms());
}

/// Holds `world` at x <= 0 under gravity, stepped with dt 2 ms and CG to 1e-12: the tests where a
/// piece cut off falls as implicit Euler moves a free body.
inline void hold_for_fall(World& world) {
    world.gravity = Vec3(0.0, 0.0, -9.81);
    world.solver.dt = 2e-3;
    world.solver.cg_tolerance = 1e-12;
    world.solver.cg_max_iterations = 2000;
    world.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    apply_constraints(world);
}

/// A square of half-size `half` on the plane through `centre` with normal `normal`.
inline std::vector<Vec3> square_on_plane(const Vec3& centre, const Vec3& normal, double half) {
    const Vec3 n = normal.normalized(), u = n.unitOrthogonal() * half, v = n.cross(n.unitOrthogonal()) * half;
    return {centre - u - v, centre + u - v, centre + u + v, centre - u + v};
}

/// Cuts `world` with a polygon now; returns the number of elements split.
inline int cut_now(World& world, const std::vector<Vec3>& polygon) {
    queue_polygon_cut(world, polygon);
    return apply_cut_events(world);
}

}  // namespace xcut::testing
