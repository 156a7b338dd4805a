// Tool devices (engine/devices/device.h) and the haptic loop (engine/devices/haptic_loop.h): a recorded cut session
// replays bit for bit, and the loop renders the coupled contact force.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "engine/error.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

/// The default scene at dt 0.03 s on 4 mm elements and the coarsest skin: a replay is about the
/// tool, not the resolution.
Scene coarse_skin_scene() {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json");
    scene.solver.dt = 0.03;
    scene.solver.cg_tolerance = 1e-4;
    scene.mesh.grid.cells = Eigen::Vector3i(15, 10, 1);
    scene.visual_subdivisions = 0;
    return scene;
}

// The default scene's scalpel incision, recorded and replayed: every bit of the state agrees.
TEST(Devices, RecordedCutSessionReplaysBitForBit) {
    const Scene scene = coarse_skin_scene();
    const fs::path dir = fs::temp_directory_path() / ("xcut_session_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    uint64_t recorded = 0;
    {
        auto sim = make_simulation(scene, false);
        sim->recorder = std::make_unique<SessionRecorder>(sim->world, dir.string());
        for (int i = 0; i < 45; ++i) step_simulation(*sim);
        ASSERT_GT(sim->world.cuts.count(), 20) << "the session cuts";
        recorded = testing::state_hash(sim->world, true);
    }
    ASSERT_TRUE(fs::exists(dir / "scalpel.csv"));
    auto replay = make_simulation(scene, false, dir.string());
    EXPECT_STREQ(replay->devices[0]->kind(), "replay");
    for (int i = 0; i < 45; ++i) step_simulation(*replay);
    EXPECT_EQ(testing::state_hash(replay->world, true), recorded);
    // A session for another scene is refused with the file named.
    EXPECT_THROW(make_simulation(scene, false, (dir / "missing").string()), InputError);
}

// In real-time mode dt follows the wall clock, so no two runs take the same steps. A recorded
// real-time session replays on its recorded time axis (steps.csv) with the device's sub-step poses:
// the time, every DOF and its state, and the wound (the cut elements) agree bit for bit.
TEST(Devices, RealTimeSessionReplaysBitForBit) {
    Scene scene = coarse_skin_scene();
    scene.solver.realtime = true;
    scene.solver.dt_min = 1e-4;  // dt follows the wall time of a step (a few ms here): every step's
    scene.solver.dt_max = 0.05;  // differs; the session runs to t = 0.5 s, into the incision
    const fs::path dir = fs::temp_directory_path() / ("xcut_rt_session_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    int steps = 0;
    uint64_t recorded = 0;
    double recorded_time = 0.0;
    std::vector<int> recorded_cuts;
    {
        auto sim = make_simulation(scene, false);
        sim->recorder = std::make_unique<SessionRecorder>(sim->world, dir.string());
        while (sim->world.time < 0.5 && steps < 5000) step_simulation(*sim), ++steps;
        ASSERT_GT(sim->world.cuts.count(), 5) << "the session cuts";
        recorded = testing::state_hash(sim->world, true);
        recorded_time = sim->world.time;
        recorded_cuts = sim->world.cuts.element;
    }
    ASSERT_TRUE(fs::exists(dir / "steps.csv"));
    auto replay = make_simulation(scene, false, dir.string());
    ASSERT_EQ(replay->replay_dt.size(), static_cast<size_t>(steps));
    std::vector<double> distinct = replay->replay_dt;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    ASSERT_GE(distinct.size(), 3u) << "the recorded dt must vary, or this replays nothing real-time";
    for (int i = 0; i < steps; ++i) step_simulation(*replay);
    EXPECT_EQ(replay->world.time, recorded_time);
    EXPECT_EQ(replay->world.cuts.element, recorded_cuts);
    EXPECT_EQ(testing::state_hash(replay->world, true), recorded);
    // One step more than the session holds is an error naming the session's file.
    try {
        step_simulation(*replay);
        ADD_FAILURE() << "stepped past the recorded session";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("steps.csv: step " + std::to_string(steps + 1)), std::string::npos)
            << e.what();
    }
    fs::remove_all(dir);
}

TEST(Devices, CoupledForceFollowsTheContactStiffnessUpToTheCoupling) {
    ContactLinearization l;
    l.position = Vec3(0.01, 0.02, 0.03);
    l.force = Vec3(0.1, 0.0, 0.5);
    l.stiffness = 500.0 * Vec3::UnitZ() * Vec3::UnitZ().transpose();  // one contact, normal z [N/m]
    const double kc = 1000.0;                                           // [N/m]
    const Vec3 f = coupled_force(l, l.position + Vec3(0.002, 0.0, -0.001), kc);
    EXPECT_NEAR(f.x(), 0.1, 1e-15) << "no contact stiffness along x: F0 only";
    EXPECT_NEAR(f.z(), 0.5 + 0.001 * 500.0 * kc / (500.0 + kc), 1e-12) << "springs in series";
    EXPECT_NEAR(coupled_force(l, l.position, kc).z(), 0.5, 1e-15);
}

// The loop ticks on its own thread and renders exactly the coupled force at the device's pose.
TEST(Devices, HapticLoopRendersTheLatestLinearization) {
    World w;
    w.tools.name = {"probe"};
    w.tools.position = {Vec3(0, 0, 0.01)};
    w.tools.orientation = {Eigen::Quaterniond::Identity()};
    w.tools.reaction_force = {Vec3(0, 0, 0.2)};
    w.tools.reaction_torque = {Vec3::Zero()};
    w.contacts.tool = {0};
    w.contacts.normal = {Vec3::UnitZ()};
    w.contacts.stiffness = {300.0};
    Keyframe a, b;
    a.position = b.position = Vec3(0, 0, 0.009);  // the hand 1 mm deeper than the physics' tool
    b.time = 1.0;
    ScriptedDevice device({a, b});
    HapticLoop loop({&device}, 1000.0, 1000.0);
    loop.publish(w);
    loop.start();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    loop.stop();
    const HapticStats s = loop.stats();
    std::printf("  haptic loop: %ld ticks in %.3f s (%.0f Hz), period p50 %.3f ms, p99 %.3f ms\n", s.ticks, s.seconds,
                s.rate_hz, s.period_p50_ms, s.period_p99_ms);
    EXPECT_GT(s.ticks, 0);
    const Vec3 expected = coupled_force(linearize_contacts(w, 0), a.position, 1000.0);
    EXPECT_EQ(device.last_force(), expected);
    EXPECT_NEAR(expected.z(), 0.2 + 0.001 * 300.0 * 1000.0 / 1300.0, 1e-12);
}

}  // namespace
}  // namespace xcut
