#pragma once
// What one `xcut view` holds besides its window: the scene with the hand tools added, the
// simulation and its devices, the physics thread and snapshot buffer, the ray caster over the
// newest snapshot, and what it writes (screenshots, the benchmark's row).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/io/scene.h"
#include "engine/simulation.h"
#include "tools/viewer/hand_tools.h"
#include "tools/viewer/orbit_camera.h"
#include "tools/viewer/physics_thread.h"
#include "tools/viewer/viewer_app.h"

namespace xcut::viewer {

/// `xcut view --bench`: the physics' steps while the window draws and while it does not, in
/// alternating 1 s phases of one run (so the machine's drift falls on both alike), and frame times.
struct BenchFigures {
    long steps_drawing = 0, steps_idle = 0;
    double seconds_drawing = 0.0, seconds_idle = 0.0;
    std::vector<double> frame_ms;
};

struct HandSizes : HandToolSizes {
    double speed = 0.0;  ///< key-driven tool speed [m/s]
};

class ViewerSession {
public:
    explicit ViewerSession(const ViewerOptions& options);
    ~ViewerSession();
    /// Takes the newest snapshot if there is one; returns whether it did.
    bool refresh();
    /// The visual surface under `ray` in the snapshot shown.
    std::optional<SurfaceHit> cast(const Ray& ray);
    /// The scene's camera if it gives one, else the headless renderer's framing of the surface.
    OrbitCamera initial_camera(int width, int height) const;
    void save_screenshot(const Image& image, const OrbitCamera& camera, const ViewerOptions& o) const;
    void report_bench(const BenchFigures& figures) const;
    /// Prints the outcome; the exit code.
    int finish() const;

    ViewerOptions options;
    std::vector<std::string> overrides;       ///< the scene's, then the hand tools'
    Scene scene;
    HandSizes sizes;
    std::unique_ptr<Simulation> sim;
    SnapshotBuffer buffer;
    std::unique_ptr<HapticLoop> haptics;      ///< when a device renders force (OpenIGTLink)
    std::unique_ptr<PhysicsThread> physics;
    std::vector<LiveDevice*> devices;         ///< per tool: its live device (every tool has one)
    std::unique_ptr<MouseScalpel> scalpel;    ///< 3D scenes
    int probe = -1;                           ///< the hand probe's tool index, -1 if none
    int first_step = 0;                       ///< the world's step when the viewer opened

private:
    SurfaceRaycaster raycaster_;
    bool raycaster_stale_ = true;
};

}  // namespace xcut::viewer
