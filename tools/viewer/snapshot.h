#pragma once
// What the viewer draws of a world: a copy taken by the physics thread after each step, handed to
// the window through a triple buffer (SnapshotBuffer). The physics writes its own slot and swaps
// it with the ready one under a lock held only for the swap of two indices; the window swaps the
// ready slot with the one it draws. Neither waits for the other's work: a step never waits for a
// frame, a frame always shows the newest complete step.
#include <Eigen/Geometry>
#include <array>
#include <mutex>
#include <string>
#include <vector>

#include "engine/world.h"

namespace xcut::viewer {

struct ToolView {
    std::string name;
    Vec3 position = Vec3::Zero();                                     ///< [m]
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< tool -> world
    bool blade = false;
    Vec3 tip = Vec3::Zero(), heel = Vec3::Zero();  ///< cutting edge in world [m]
    std::vector<Vec3> shape_vertices;              ///< contact shape, triangulated, in world [m]
    std::vector<std::array<int, 3>> shape_triangles;
    Vec3 force = Vec3::Zero();                     ///< the tissue's reaction on the tool [N]
};

/// Which overlays the physics thread copies (the window sets them; the rest costs nothing).
struct SnapshotOptions {
    bool mesh = false;      ///< the simulation mesh's edges
    bool virtuals = false;  ///< the virtual elements' edges
};

struct Snapshot {
    int step = 0;
    double time = 0.0, dt = 0.0;    ///< [s]
    double step_ms = 0.0;           ///< wall time of the step [ms]
    double realtime_factor = 0.0;   ///< simulated / wall time over the last second [-]
    // The visual surface.
    std::vector<Vec3> surface;                    ///< [m]
    std::vector<std::array<int, 3>> triangles;
    std::vector<uint8_t> cut_face;
    // Overlays, as line segments (pairs of points) [m].
    std::vector<Vec3> mesh_lines, virtual_lines, quad_lines;
    std::vector<Vec3> contact_points, contact_normals;
    std::vector<ToolView> tools;
    // Readouts.
    std::vector<std::string> systems;
    std::vector<double> system_ms;
    std::string linear;
    int cg_iterations = 0;
    double cg_residual = 0.0;
    int dofs = 0, enriched_nodes = 0, elements_split = 0;
    int pieces = 0, pieces_freed = 0;  ///< pieces of tissue now, and those cuts freed (components/pieces.h)
    double kinetic = 0.0, elastic = 0.0;  ///< [J]
    bool dim3 = true;
};

/// Copies what `options` asks for from `world` into `out` (its buffers reused).
void take_snapshot(const World& world, const SnapshotOptions& options, Snapshot& out);

/// The edges of the listed elements as node pairs, each once.
std::vector<std::array<int, 2>> element_edges(const Elements& elements, const std::vector<int>& which);

class SnapshotBuffer {
public:
    /// The physics' slot: fill it, then publish().
    Snapshot& back() { return slots_[back_]; }
    void publish();
    /// The window: takes the newest published snapshot if there is one since the last call;
    /// returns whether it did. front() is then stable until the next acquire().
    bool acquire();
    const Snapshot& front() const { return slots_[front_]; }

private:
    std::array<Snapshot, 3> slots_;
    int back_ = 0, ready_ = 1, front_ = 2;
    bool fresh_ = false;
    std::mutex mutex_;  ///< guards the three indices and `fresh_` only
};

}  // namespace xcut::viewer
