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
#include "systems/surface/mapping_system.h"

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

/// The X incision's second blade on the default skin (scenes/skin_slab.json), as a --set override:
/// a scalpel that waits until the default incision is made, then crosses it at x = 0.016-0.046 m.
inline const std::string kCrossingScalpel =
    R"(tools+={"name": "cross", "blade": {"tip": [0, 0, -0.003], "heel": [0, 0, 0.004]},
        "trajectory": [{"time": 0, "position": [0.016, 0.0203, 0.03]}, {"time": 1.25, "position": [0.016, 0.0203, 0.03]},
                       {"time": 1.3, "position": [0.016, 0.0203, 0]}, {"time": 2.0, "position": [0.046, 0.0203, 0]}]})";

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

/// The linear patch test: every node on the boundary of the box [0, size] (on its first `dims` axes)
/// held at X + A X, the others solved statically from rest with jacobi and with cholesky; every node
/// must land on X + A X (1e-10 of the box's displacement).
inline void expect_patch_test(World& w, const Eigen::Matrix3d& A, const Vec3& size, int dims) {
    auto boundary = [&](const Vec3& p) {
        for (int k = 0; k < dims; ++k)
            if (std::abs(p[k]) < 1e-12 || std::abs(p[k] - size[k]) < 1e-12) return true;
        return false;
    };
    int interior = 0;
    for (int i = 0; i < w.nodes.count(); ++i) {
        if (boundary(w.nodes.rest[i])) {
            w.constraints.nodes.push_back(i);
            w.nodes.position[i] = w.nodes.rest[i] + A * w.nodes.rest[i];
        } else {
            ++interior;
        }
    }
    apply_constraints(w);
    ASSERT_GT(interior, 10);
    const uint8_t all = dims == 3 ? 7 : 3;
    for (const std::string method : {"jacobi", "cholesky"}) {
        w.solver.linear = method;
        for (int i = 0; i < w.nodes.count(); ++i)
            if ((w.nodes.fixed[i] & all) != all) w.nodes.position[i] = w.nodes.rest[i];
        const StaticResult r = static_solve(w, xcut_step_terms(), 1e-10, 10, 1e-12, 5000);
        EXPECT_TRUE(r.converged) << method;
        double worst = 0.0;
        for (int i = 0; i < w.nodes.count(); ++i)
            worst = std::max(worst, (w.nodes.position[i] - w.nodes.rest[i] - A * w.nodes.rest[i]).norm());
        EXPECT_LT(worst, 1e-10 * (A * size).norm()) << method;
    }
}

/// What kSteps implicit Euler steps under gravity did to a world cut in two: the free fall
/// g dt^2 n (n + 1) / 2 [m], the largest distance of a node of the free part from it, the largest
/// displacement of the held part [m], the free part's node count.
struct FallCheck {
    double fall = 0.0, worst = 0.0, held = 0.0;
    int free_nodes = 0;
};
/// Steps `w` `steps` times; part(d): 1 for a DOF node of the free part, 0 for the held one, -1 for
/// none (a node no element holds).
template <class Part>
FallCheck step_and_fall(World& w, int steps, Part&& part) {
    for (int s = 0; s < steps; ++s) step_world(w);
    FallCheck c;
    c.fall = w.gravity.norm() * w.solver.dt * w.solver.dt * steps * (steps + 1) / 2.0;
    const Vec3 down = w.gravity.normalized() * c.fall;
    for (int d = 0; d < w.nodes.count(); ++d) {
        const int p = part(d);
        if (p < 0) continue;
        const Vec3 u = w.nodes.position[d] - w.nodes.rest[d];
        if (p == 0) {
            c.held = std::max(c.held, u.norm());
        } else {
            ++c.free_nodes;
            c.worst = std::max(c.worst, (u - down).norm());
        }
    }
    return c;
}

/// The mean tip deflection against `axis` of a beam held at x = 0 whose tip is at x = length, solved
/// statically with `method` [m].
inline double clamped_tip_deflection(World& w, const std::string& method, double length, int axis) {
    w.solver.linear = method;
    const StaticResult r = static_solve(w, xcut_step_terms(), 1e-9, 10, 1e-12, 20000);
    EXPECT_TRUE(r.converged) << method << ": residual " << r.residual;
    double sum = 0.0;
    int count = 0;
    for (int i = 0; i < w.nodes.count(); ++i)
        if (std::abs(w.nodes.rest[i].x() - length) < 1e-12) sum -= w.nodes.position[i][axis] - w.nodes.rest[i][axis], ++count;
    return sum / count;
}

/// A body clamped at x = 0 and stretched by delta at x = length (nu = 0), solved statically with
/// `method`: every DOF node at u = (delta x / length, 0, 0) (1e-9 of delta) and the strain energy
/// `closed` (1e-8).
inline void expect_uniform_stretch(World& w, const std::string& method, double delta, double length, double closed) {
    w.solver.linear = method;
    const StaticResult r = static_solve(w, xcut_step_terms(), 1e-11, 10, 1e-13, 5000);
    EXPECT_TRUE(r.converged);
    double worst = 0.0;
    for (int d = 0; d < w.nodes.count(); ++d) {
        const Vec3 u = w.nodes.position[d] - w.nodes.rest[d];
        worst = std::max(worst, (u - Vec3(delta * w.nodes.rest[d].x() / length, 0.0, 0.0)).norm());
    }
    EXPECT_LT(worst, 1e-9 * delta);
    update_rotations(w);
    compute_forces(w);
    EXPECT_NEAR(w.forces.elastic_energy, closed, 1e-8 * closed);
}

/// HRZ lumped masses of a world of (uncut) quadratic elements: they sum to rho times the volume,
/// their centre is the elements' volume centroid, each is positive.
inline void expect_masses_keep_total_and_centre(const World& w, double density) {
    const int npe = w.elements.nodes_per_element();
    double mass = 0.0, volume = 0.0;
    Vec3 centre = Vec3::Zero(), exact = Vec3::Zero();
    for (int i = 0; i < w.nodes.count(); ++i) mass += w.nodes.mass[i], centre += w.nodes.mass[i] * w.nodes.rest[i];
    for (int e = 0; e < w.elements.count(); ++e) {
        Vec3 c = Vec3::Zero();
        for (int a = 0; a < npe; ++a) c += w.nodes.rest[w.elements.nodes[e][a]] / npe;
        volume += w.elements.rest_volume[e], exact += w.elements.rest_volume[e] * c;
    }
    EXPECT_NEAR(mass, density * volume, 1e-12 * mass);
    EXPECT_LT((centre / mass - exact / volume).norm(), 1e-12);
    for (int i = 0; i < w.nodes.count(); ++i) EXPECT_GT(w.nodes.mass[i], 0.0) << i;
}

/// After an XFEM cut of quadratic elements: every mid-edge node the cut met has the side
/// `side_of_rest(X)` gives its rest point; some did, and some on a split edge got a phantom.
template <class Side>
void expect_mid_edge_nodes_take_their_points_side(const World& w, Side&& side_of_rest) {
    int met = 0, split_with_phantom = 0;
    const QuadraticElements& q = w.quadratic;
    for (int m = q.first_edge_node; m < w.mesh_nodes; ++m) {
        if (w.enriched.sign[m] == 0) continue;
        ++met;
        EXPECT_EQ(w.enriched.sign[m], side_of_rest(w.nodes.rest[m])) << m;
        const auto& [a, b] = q.edge_of_node[m - q.first_edge_node];
        if (w.enriched.sign[a] != w.enriched.sign[b]) split_with_phantom += w.enriched.phantom[m] >= 0;
    }
    EXPECT_GT(met, 0);
    EXPECT_GT(split_with_phantom, 0);
}

/// Holds `w` at x <= 0 and at x >= length, the latter moved by delta along x: a stretch test.
inline void clamp_and_stretch(World& w, double length, double delta) {
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    w.constraints.boxes.push_back({Vec3(length - 1e-9, -1, -1), Vec3(1, 1, 1), 7, Vec3(delta, 0.0, 0.0)});
    apply_constraints(w);
}

/// The stretch test along a cut through a body's whole length (nu = 0), with cholesky and jacobi:
/// make() the body, clamped at x = 0 and stretched by delta = 3e-4 m at x = length, cut(w) cuts it;
/// it must strain uniformly and store E (delta / length)^2 V / 2 (`young` E, `volume` V).
template <class Make, class Cut>
void expect_stretch_along_a_cut(Make&& make, Cut&& cut, double length, double young, double volume) {
    for (const std::string method : {"cholesky", "jacobi"}) {
        SCOPED_TRACE(method);
        World w = make();
        const double delta = 3e-4, eps = delta / length;
        clamp_and_stretch(w, length, delta);
        ASSERT_GT(cut(w), 0);
        expect_uniform_stretch(w, method, delta, length, 0.5 * young * eps * eps * volume);
    }
}

/// Places every node at bent(rest) and the visual and collision surfaces (subdivided `subdivisions`
/// times) on it.
template <class Bent>
void place_bent_with_surfaces(World& w, Bent&& bent, int subdivisions) {
    for (int i = 0; i < w.nodes.count(); ++i) w.nodes.position[i] = bent(w.nodes.rest[i]);
    build_surface(w, w.visual, subdivisions);
    build_surface(w, w.collision, subdivisions);
    update_surface_positions(w);
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
