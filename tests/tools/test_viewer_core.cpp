// The viewer's window-free parts (tools/viewer): the snapshot handover between the physics thread
// and the window, the physics thread's controls and failure path, the camera against the headless
// renderer's rays, the hand scalpel's poses, and the input script's errors.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "engine/error.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"
#include "tools/viewer/hand_tools.h"
#include "tools/viewer/orbit_camera.h"
#include "tools/viewer/physics_thread.h"
#include "tools/viewer/scripted_input.h"
#include "tools/viewer/viewer_timing.h"

namespace xcut::viewer {
namespace {

Scene coarse_skin(const std::vector<std::string>& more = {}) {
    std::vector<std::string> o = {"solver.dt=0.02", "mesh.element_size=0.004", "visual.subdivisions=0"};
    o.insert(o.end(), more.begin(), more.end());
    return load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json", o);
}

// The window takes the newest published snapshot, whole: never a slot the physics is writing.
TEST(ViewerSnapshots, AcquireTakesTheNewestWholeSnapshot) {
    SnapshotBuffer b;
    EXPECT_FALSE(b.acquire()) << "nothing published yet";
    for (int i = 1; i <= 3; ++i) b.back().step = i, b.back().surface.assign(i, Vec3::Zero()), b.publish();
    ASSERT_TRUE(b.acquire());
    EXPECT_EQ(b.front().step, 3) << "older snapshots are skipped, not queued";
    EXPECT_FALSE(b.acquire());
    // A writer publishing without pause beside a reader: the reader's front stays whole and only moves forward.
    std::atomic<bool> done{false};
    std::thread writer([&] {
        for (int i = 4; i < 20000; ++i) {
            Snapshot& s = b.back();
            s.step = i, s.time = 0.5 * i, s.surface.assign(i % 7, Vec3::Constant(i));
            b.publish();
        }
        done = true;
    });
    int last = 3, seen = 0;
    for (;;) {
        const bool finished = done;  // read before acquiring: the last publish is then always taken
        if (!b.acquire()) {
            if (finished) break;
            continue;
        }
        const Snapshot& s = b.front();
        ASSERT_GT(s.step, last);
        ASSERT_EQ(s.time, 0.5 * s.step);
        ASSERT_EQ(s.surface.size(), static_cast<size_t>(s.step % 7));
        for (const Vec3& p : s.surface) ASSERT_EQ(p.x(), s.step);
        last = s.step, ++seen;
    }
    writer.join();
    EXPECT_GT(seen, 0);
    EXPECT_EQ(last, 19999) << "the newest one is the last one taken";
}

// Each allowed step is published as a snapshot and, when asked, its timing kept (the elements it split).
TEST(ViewerPhysics, StepsWhenAllowedSnapshotsAndTimesEachStep) {
    const Scene scene = coarse_skin();
    auto sim = make_simulation(scene, false);
    SnapshotBuffer buffer;
    PhysicsThread physics(*sim, buffer);
    physics.set_lockstep(true);
    physics.keep_timings(true);
    physics.start();
    ASSERT_TRUE(buffer.acquire());
    EXPECT_EQ(buffer.front().step, 0) << "the initial state is published at start";
    physics.allow_steps(5);
    for (int i = 0; i < 2000 && !(physics.idle() && physics.steps_done() == 5); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_EQ(physics.steps_done(), 5);
    ASSERT_TRUE(buffer.acquire());
    EXPECT_EQ(buffer.front().step, sim->world.step);
    EXPECT_EQ(buffer.front().surface.size(), sim->world.visual.position.size());
    EXPECT_EQ(buffer.front().systems, sim->world.metrics.system_names);
    EXPECT_GT(buffer.front().cg_iterations, 0);
    physics.stop();
    EXPECT_FALSE(physics.failed());
    const std::vector<StepTiming> t = physics.timings();
    ASSERT_EQ(t.size(), 5u);
    for (size_t k = 1; k < t.size(); ++k) EXPECT_GE(t[k].wall_end, t[k - 1].wall_end);
    for (const StepTiming& step : t) {
        EXPECT_GT(step.step_ms, 0.0);
        EXPECT_EQ(step.split, 0);
    }
}

// Frames every 33 ms with one of 100 ms, a pause of a second left out; steps every 10 ms, the one
// that split ending 25 ms after the one before.
TEST(ViewerTiming, IntervalsAgainstTheirMedians) {
    TimingLog log;
    double t = 0.0;
    for (int k = 0; k < 20; ++k) log.frame_start.push_back(t), t += k == 10 ? 0.1 : 0.033;
    log.frame_start.push_back(t + 1.0);  // the window sat paused: not an interval
    t = 0.0;
    for (int k = 0; k < 30; ++k) {
        t += k == 15 ? 0.025 : 0.010;
        log.steps.push_back({t, k == 15 ? 7.0 : 3.0, k == 15 ? 4 : 0});
    }
    const TimingFigures f = timing_figures(log, 0.0, 10.0);
    EXPECT_EQ(f.frames.count, 19);
    EXPECT_NEAR(f.frames.p50, 33.0, 1e-9);
    EXPECT_NEAR(f.frames.max, 100.0, 1e-9);
    EXPECT_EQ(f.frames.over_twice, 1);
    EXPECT_EQ(f.updates.count, 29);
    EXPECT_NEAR(f.updates.p50, 10.0, 1e-9);
    EXPECT_NEAR(f.updates.max, 25.0, 1e-9);
    EXPECT_EQ(f.updates.over_twice, 1);
    EXPECT_EQ(f.split_steps, 1);
    EXPECT_NEAR(f.split_update_max, 25.0, 1e-9);
    EXPECT_NEAR(f.split_step_max, 7.0, 1e-12);
    EXPECT_NEAR(f.step_p50, 3.0, 1e-12);
    // The cut: the split step's end (0.175 s), 0.052 s either side; only what ends inside counts.
    double from = 0.0, to = 0.0;
    ASSERT_TRUE(cut_window(log, 0.052, from, to));
    EXPECT_NEAR(from, log.steps[15].wall_end - 0.052, 1e-12);
    EXPECT_NEAR(to, log.steps[15].wall_end + 0.052, 1e-12);
    const TimingFigures cut = timing_figures(log, from, to);
    EXPECT_EQ(cut.updates.count, 9);  // the steps ending at 0.13-0.225 s
    EXPECT_EQ(cut.split_steps, 1);
    EXPECT_FALSE(cut_window(TimingLog{}, 0.05, from, to));
}

// A run that blows up stops the physics with the watchdog's message; the window stays up to say so.
TEST(ViewerPhysics, ANumericalFailureStopsThePhysicsWithItsMessage) {
    const Scene scene = coarse_skin({"gravity=[0, 0, -1e300]"});
    auto sim = make_simulation(scene, false);
    SnapshotBuffer buffer;
    PhysicsThread physics(*sim, buffer);
    physics.set_paced(false);
    physics.start();
    for (int i = 0; i < 5000 && !physics.failed(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_TRUE(physics.failed());
    EXPECT_TRUE(physics.idle());
    EXPECT_FALSE(physics.error().empty());
    physics.stop();
}

// The window's camera casts the headless renderer's rays (engine/io/render.cpp), and its view and
// projection put a point where that ray says.
TEST(ViewerCamera, MatchesTheHeadlessRenderer) {
    Camera c;
    c.position = Vec3(0.1, -0.2, 0.3), c.target = Vec3(0.02, 0.01, 0.0), c.up = Vec3::UnitY(), c.fov_deg = 40.0;
    const OrbitCamera o = OrbitCamera::from(c);
    const int w = 800, h = 500;
    const Ray centre = o.ray(0.5 * w, 0.5 * h, w, h);
    EXPECT_LT((centre.direction - (c.target - c.position).normalized()).norm(), 1e-12);
    const Ray r = o.ray(123.5, 456.5, w, h);  // a pixel centre, as the renderer samples it
    const Vec3 p = r.origin + 0.2 * r.direction;
    const Eigen::Vector4f clip = o.projection(double(w) / h) * o.view() * Eigen::Vector4f(float(p.x()), float(p.y()), float(p.z()), 1.f);
    const double px = (clip.x() / clip.w() + 1.0) * 0.5 * w, py = (1.0 - clip.y() / clip.w()) * 0.5 * h;
    EXPECT_NEAR(px, 123.5, 1e-3);
    EXPECT_NEAR(py, 456.5, 1e-3);
    OrbitCamera moved = o;
    moved.orbit(0.3, -0.2);
    EXPECT_NEAR((moved.position - moved.target).norm(), (o.position - o.target).norm(), 1e-12) << "orbit keeps the distance";
    moved.zoom(0.5);
    EXPECT_NEAR((moved.position - moved.target).norm(), 0.5 * (o.position - o.target).norm(), 1e-12);
}

// A press plunges the blade's tip to the depth below the point under the cursor along its normal,
// a drag carries it there, a release lifts it above the skin; a press off the skin does nothing.
TEST(ViewerScalpel, PressDragReleaseOnTheSurface) {
    Snapshot s;  // a 10 cm square at z = 0
    s.surface = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0), Vec3(0, 0.1, 0)};
    s.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.cut_face = {0, 0};
    SurfaceRaycaster caster;
    caster.build(s);
    const HandToolSizes sizes = hand_tool_sizes(Vec3(0, 0, -0.002), Vec3(0.1, 0.1, 0));
    EXPECT_NEAR(sizes.depth, 0.0025, 1e-15) << "through a 2 mm sheet";
    LiveDevice device(Keyframe{}, "test");
    MouseScalpel scalpel(device, sizes);
    Ray down;
    down.origin = Vec3(0.03, 0.04, 0.5), down.direction = -Vec3::UnitZ();
    const auto hit = caster.cast(down);
    ASSERT_TRUE(hit);
    EXPECT_LT((hit->point - Vec3(0.03, 0.04, 0)).norm(), 1e-7);
    EXPECT_LT((hit->normal - Vec3::UnitZ()).norm(), 1e-12) << "the normal faces the ray";
    scalpel.hover(hit);
    EXPECT_NEAR(device.target().position.z(), sizes.lift, 1e-7) << "hovering above";
    scalpel.press(hit);
    EXPECT_TRUE(scalpel.cutting());
    EXPECT_NEAR(device.target().position.z(), -sizes.depth, 1e-7);
    down.origin = Vec3(0.05, 0.04, 0.5);
    scalpel.drag(down, caster.cast(down));
    EXPECT_LT((device.target().position - Vec3(0.05, 0.04, -sizes.depth)).norm(), 1e-7);
    Ray off;  // off the body: the tangent plane of the entry carries the blade
    off.origin = Vec3(0.2, 0.04, 0.5), off.direction = -Vec3::UnitZ();
    EXPECT_FALSE(caster.cast(off));
    scalpel.drag(off, caster.cast(off));
    EXPECT_LT((device.target().position - Vec3(0.2, 0.04, -sizes.depth)).norm(), 1e-7);
    scalpel.release();
    EXPECT_FALSE(scalpel.cutting());
    EXPECT_NEAR(device.target().position.z(), sizes.lift, 1e-7);
    scalpel.press(std::nullopt);
    EXPECT_FALSE(scalpel.cutting()) << "a press off the skin";
}

TEST(ViewerInput, ScriptErrorsNameTheLine) {
    const auto dir = testing::temp_dir("viewer_input");
    std::ofstream(dir / "ok.txt") << "# a drag\n0 hover 10 20\n1 press 10 20\n2 drag 30 20  # on\n3 release\n3 key space\n4 wheel -2\n";
    const auto events = read_input_script((dir / "ok.txt").string());
    ASSERT_EQ(events.size(), 6u);
    EXPECT_EQ(events[2].kind, InputEvent::kDrag);
    EXPECT_EQ(events[2].x, 30.0);
    EXPECT_EQ(events[4].key, "space");
    EXPECT_EQ(events[5].x, -2.0);
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"0 hover 10\n", "line 1"}, {"0 jump 1 2\n", "unknown event"}, {"5 release\n2 release\n", "line 2"},
        {"x hover 1 2\n", "frame number"}, {"0 release now\n", "unexpected"}};
    for (const auto& [text, expect] : bad) {
        std::ofstream(dir / "bad.txt") << text;
        try {
            read_input_script((dir / "bad.txt").string());
            ADD_FAILURE() << "accepted: " << text;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("bad.txt"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(read_input_script((dir / "missing.txt").string()), InputError);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace xcut::viewer
