#include "tools/viewer/viewer_session.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>

#include "engine/error.h"
#include "systems/pipeline.h"

namespace xcut::viewer {

namespace {

HandSizes sizes_of(const MeshData& mesh) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Vec3& p : mesh.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    HandSizes s;
    static_cast<HandToolSizes&>(s) = hand_tool_sizes(lo, hi);
    s.speed = 0.1 * (hi - lo).maxCoeff();
    return s;
}

}  // namespace

ViewerSession::ViewerSession(const ViewerOptions& o) : options(o), overrides(o.overrides) {
    const Scene base = load_scene(o.scene, overrides);
    const MeshData mesh = load_scene_mesh(base);
    if (mesh.dim == 3) {  // the hand scalpel; the probe where there is a collision surface to touch
        sizes = sizes_of(mesh);
        for (const std::string& t : hand_tool_overrides(sizes, base.collision_subdivisions >= 0)) overrides.push_back(t);
    }
    scene = load_scene(o.scene, overrides);
    std::vector<LiveDevice*> made;  // the hand tools' devices, made by build_simulation through this factory
    register_device_type("viewer", [&made](const DeviceSpec&, const std::string&, const Keyframe& start) {
        auto d = std::make_unique<LiveDevice>(start, "viewer");
        made.push_back(d.get());
        return d;
    });
    sim = make_simulation(scene, false);
    first_step = sim->world.step;
    devices.assign(sim->world.tools.count(), nullptr);
    for (int i = 0, hand = 0; i < sim->world.tools.count(); ++i) {
        if (scene.devices[i].type == "viewer") {
            devices[i] = made[hand++];
        } else if (scene.devices[i].type == "scripted") {  // a scene tool: scripted until taken over
            auto d = std::make_unique<LiveDevice>(sim->world.tools.trajectory[i], "scripted");
            devices[i] = d.get();
            sim->devices[i] = std::move(d);
        }
        if (sim->world.tools.name[i] == kHandScalpel) scalpel = std::make_unique<MouseScalpel>(*devices[i], sizes);
        if (sim->world.tools.name[i] == kHandProbe) probe = i;
    }
    if (!o.record.empty())
        sim->recorder = std::make_unique<SessionRecorder>(sim->world, o.record, SessionInfo{o.scene, overrides});
    haptics = start_haptics(*sim, false);  // a network haptic device gets its force at 1 kHz
    physics = std::make_unique<PhysicsThread>(*sim, buffer);
    fmt::print("view {} ({}): {} nodes, {} elements, {} tools ({}), {} threads\n", scene.name, o.scene,
               sim->world.nodes.count(), sim->world.elements.count(), sim->world.tools.count(),
               scalpel ? "hand scalpel on the left button" : "2D: no hand scalpel",
               o.threads);
}

ViewerSession::~ViewerSession() {
    if (physics) physics->stop();
    if (haptics) haptics->stop();
}

bool ViewerSession::refresh() {
    const bool fresh = buffer.acquire();
    raycaster_stale_ |= fresh;
    return fresh;
}

std::optional<SurfaceHit> ViewerSession::cast(const Ray& ray) {
    if (raycaster_stale_) raycaster_.build(buffer.front()), raycaster_stale_ = false;
    return raycaster_.cast(ray);
}

OrbitCamera ViewerSession::initial_camera(int width, int height) const {
    const Camera c = scene.camera.automatic ? frame_surface(sim->world.visual, width, height) : scene.camera;
    return OrbitCamera::from(c);
}

void ViewerSession::save_screenshot(const Image& image, const OrbitCamera& camera, const ViewerOptions& o) const {
    write_png(image, o.screenshot);
    fmt::print("screenshot: {} (step {}, t = {:.4g} s, {} elements split)\n", o.screenshot, buffer.front().step,
               buffer.front().time, buffer.front().elements_split);
    if (o.reference.empty()) return;
    SurfaceMesh surface;  // the snapshot drawn, rendered headless from the same camera
    surface.position = buffer.front().surface;
    surface.triangles = buffer.front().triangles;
    surface.cut_face = buffer.front().cut_face;
    write_png(render_surface(surface, camera.as_render_camera(image.width, image.height)), o.reference);
    fmt::print("reference render: {}\n", o.reference);
}

void ViewerSession::report_bench(const BenchFigures& b) const {
    std::vector<double> f = b.frame_ms;
    std::sort(f.begin(), f.end());
    auto pct = [&f](double p) { return f.empty() ? 0.0 : f[std::min(f.size() - 1, size_t(p * f.size()))]; };
    const double drawn = b.steps_drawing / std::max(b.seconds_drawing, 1e-9), idle = b.steps_idle / std::max(b.seconds_idle, 1e-9);
    const double ratio = idle > 0.0 ? drawn / idle : 0.0;
    fmt::print("viewer bench {} ({} threads, {:.0f} s in 1 s phases, drawing and not): physics {:.1f} steps/s without "
               "frames, {:.1f} steps/s while the window draws ({:.1f} %); {} frames, a frame's work p50 {:.2f} ms, p99 {:.2f} ms\n",
               scene.name, options.threads, b.seconds_drawing + b.seconds_idle, idle, drawn, 100.0 * ratio, f.size(),
               pct(0.5), pct(0.99));
    if (options.bench_csv.empty()) return;
    const bool header = !std::filesystem::exists(options.bench_csv);
    std::ofstream out(options.bench_csv, std::ios::app);
    if (!out) throw InputError(options.bench_csv, "--bench-csv", "cannot write the benchmark file");
    if (header) out << "scene,threads,seconds,idle_steps_per_s,drawing_steps_per_s,ratio,frames,frame_work_p50_ms,frame_work_p99_ms\n";
    out << fmt::format("{},{},{:.2f},{:.2f},{:.2f},{:.4f},{},{:.3f},{:.3f}\n", scene.name, options.threads,
                       b.seconds_drawing + b.seconds_idle, idle, drawn, ratio, f.size(), pct(0.5), pct(0.99));
}

int ViewerSession::finish() const {
    const World& w = sim->world;
    if (physics->failed()) {
        fmt::print(stderr, "error: the simulation stopped at step {}: {}\n", w.step, physics->error());
        return 3;
    }
    fmt::print("done: t = {:.4g} s, {} steps; {} elements split\n", w.time, physics->steps_done(),
               w.cuts.count() + w.snap.elements_split);
    if (!options.record.empty()) fmt::print("session recorded: {} (xcut run {} --replay {})\n", options.record, options.scene, options.record);
    return 0;
}

}  // namespace xcut::viewer
