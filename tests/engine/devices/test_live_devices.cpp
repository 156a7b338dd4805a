// Live devices (engine/devices/live_device.h): a pose set by another thread becomes the end of the
// step's segment, a blade is swept along it, and the session records and replays bit for bit with
// the tools it added (session.json); a scene's "device" field and the override that appends tools.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "engine/devices/live_device.h"
#include "engine/error.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;
using testing::state_hash;

Keyframe at(double t, const Vec3& p) {
    Keyframe k;
    k.time = t, k.position = p;
    return k;
}

TEST(LiveDevices, TargetEndsTheStepAndEarlierTimesInterpolate) {
    LiveDevice d(at(0.0, Vec3::Zero()), "test");
    EXPECT_EQ(d.pose(0.0).position, Vec3::Zero());
    d.set_target(Vec3(0.01, 0, 0), Eigen::Quaterniond::Identity());
    EXPECT_EQ(d.pose(0.1).position, Vec3(0.01, 0, 0)) << "the step's end is the newest target";
    d.set_target(Vec3(0.03, 0, 0), Eigen::Quaterniond::Identity());  // moved on while the step samples
    EXPECT_NEAR(d.pose(0.05).position.x(), 0.005, 1e-15) << "inside the step: on the step's segment";
    EXPECT_EQ(d.haptic_pose(0.05).position, Vec3(0.03, 0, 0)) << "the haptic loop couples to the hand now";
    EXPECT_EQ(d.pose(0.2).position, Vec3(0.03, 0, 0));
    EXPECT_NEAR(d.pose(0.15).position.x(), 0.02, 1e-15);
}

// Targets given within one step make its path, evenly over the step: a press, a drag and a release
// between two steps are all swept.
TEST(LiveDevices, TargetsGivenWithinOneStepMakeItsPath) {
    LiveDevice d(at(0.0, Vec3::Zero()), "test");
    d.pose(0.0);
    for (const Vec3& p : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(4, 0, -1), Vec3(4, 0, 1)})
        d.set_target(p, Eigen::Quaterniond::Identity());
    const auto near = [&](double t, const Vec3& p) { return (d.pose(t).position - p).norm() < 1e-12; };
    EXPECT_TRUE(near(0.4, Vec3(4, 0, 1))) << "the step's end is the newest target";
    EXPECT_TRUE(near(0.1, Vec3(0, 0, 1)));
    EXPECT_TRUE(near(0.2, Vec3(0, 0, -1))) << "pressed";
    EXPECT_TRUE(near(0.25, Vec3(2, 0, -1))) << "dragged while pressed";
    EXPECT_TRUE(near(0.3, Vec3(4, 0, -1)));
    d.set_target(Vec3(5, 0, 1), Eigen::Quaterniond::Identity());
    EXPECT_TRUE(near(0.5, Vec3(5, 0, 1)));
    EXPECT_TRUE(near(0.45, Vec3(4.5, 0, 1))) << "one target: the straight segment, as before";
}

TEST(LiveDevices, FollowsItsScriptUntilTakenOver) {
    LiveDevice d({at(0.0, Vec3::Zero()), at(1.0, Vec3(0.1, 0, 0))}, "test");
    EXPECT_FALSE(d.live());
    d.set_target(Vec3(5, 5, 5), Eigen::Quaterniond::Identity());  // ignored while scripted
    EXPECT_NEAR(d.pose(0.5).position.x(), 0.05, 1e-15);
    d.take_over();
    EXPECT_TRUE(d.live());
    EXPECT_NEAR(d.pose(0.6).position.x(), 0.05, 1e-15) << "taken where the script left it";
    d.set_target(Vec3(0.05, 0.01, 0), Eigen::Quaterniond::Identity());
    EXPECT_EQ(d.pose(0.7).position, Vec3(0.05, 0.01, 0));
}

/// The default scene, coarse, with a second scalpel of the kind the viewer adds (appended with
/// "tools+="), parked off the body.
std::vector<std::string> live_scalpel_overrides() {
    return {"solver.dt=0.03", "solver.cg_tolerance=1e-4", "mesh.element_size=0.004", "visual.subdivisions=0",
            R"(tools+={"name": "hand", "blade": {"tip": [0, 0, -0.003], "heel": [0, 0, 0.004]},
                "trajectory": [{"time": 0, "position": [0.01, -0.02, 0]}], "device": {"type": "viewer"}})"};
}

/// Registers the "viewer" device type as live devices collected in `hands`.
void register_hands(std::vector<LiveDevice*>& hands) {
    register_device_type("viewer", [&hands](const DeviceSpec&, const std::string&, const Keyframe& start) {
        auto d = std::make_unique<LiveDevice>(start, "viewer");
        hands.push_back(d.get());
        return d;
    });
}

/// Cut elements left of the scripted scalpel's line x = 31 mm: the hand's.
int cut_by_hand(const World& w) {
    int n = 0;
    for (int e : w.cuts.element) {
        double x = 0.0;
        for (int v : w.elements.nodes[e]) x += 0.25 * w.nodes.rest[v].x();
        n += x < 0.026 ? 1 : 0;
    }
    return n;
}

// A hand-driven incision across x at y = 10 mm (the scripted scalpel never reaches it): it cuts,
// it is recorded with the session's overrides, and `--replay` rebuilds the scene with the added
// tool and gives the same bits.
TEST(LiveDevices, HandDrivenCutRecordsAndReplaysWithTheAddedTool) {
    const std::string scene_file = std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json";
    const std::vector<std::string> overrides = live_scalpel_overrides();
    Scene scene = load_scene(scene_file, overrides);
    ASSERT_EQ(scene.tools.count(), 2);
    EXPECT_EQ(scene.devices[1].type, "viewer");
    EXPECT_THROW(make_simulation(scene, false), InputError) << "no factory: `xcut run` has no viewer";
    std::vector<LiveDevice*> hands;
    register_hands(hands);
    const fs::path dir = testing::temp_dir("live_session");
    uint64_t recorded = 0;
    int cuts = 0;
    {
        auto sim = make_simulation(scene, false);
        ASSERT_EQ(hands.size(), 1u);
        sim->recorder = std::make_unique<SessionRecorder>(sim->world, dir.string(), SessionInfo{scene_file, overrides});
        for (int i = 0; i < 20; ++i) {  // the hand draws across x at 2 mm a step, 0.5 mm deep
            hands[0]->set_target(Vec3(0.01 + 0.002 * i, 0.01, -0.0005), Eigen::Quaterniond::Identity());
            step_simulation(*sim);
        }
        cuts = sim->world.cuts.count();
        recorded = state_hash(sim->world);
        EXPECT_GT(cut_by_hand(sim->world), 10) << "the hand's blade cut along its path";
    }
    const std::vector<std::string> session = read_session_overrides(dir.string());
    EXPECT_EQ(session, overrides);
    auto replay = make_simulation(load_scene(scene_file, session), false, dir.string());
    for (int i = 0; i < 20; ++i) step_simulation(*replay);
    EXPECT_EQ(replay->world.cuts.count(), cuts);
    EXPECT_EQ(state_hash(replay->world), recorded);
    fs::remove_all(dir);
}

// A hand quicker than the physics: the whole incision (press, a 40 mm drag, release) given between
// two steps still cuts along its path (only the newest target, the lifted blade, was kept before:
// a quick drag in a viewer slowed by a busy machine cut nothing).
TEST(LiveDevices, ADragWithinOneStepCuts) {
    Scene scene = load_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json", live_scalpel_overrides());
    std::vector<LiveDevice*> hands;
    register_hands(hands);
    auto sim = make_simulation(scene, false);
    ASSERT_EQ(hands.size(), 1u);
    step_simulation(*sim);
    const auto target = [&](double x, double z) { hands[0]->set_target(Vec3(x, 0.01, z), Eigen::Quaterniond::Identity()); };
    target(0.01, 0.01);  // above the skin, then down through it
    for (int i = 0; i <= 20; ++i) target(0.01 + 0.002 * i, -0.0005);
    target(0.05, 0.01);  // lifted
    step_simulation(*sim);
    EXPECT_GT(cut_by_hand(sim->world), 10) << "the blade swept the drag's path within the step";
}

TEST(LiveDevices, SceneDeviceFieldsAreChecked) {
    const std::string scene_file = std::string(XCUT_SOURCE_DIR) + "/scenes/skin_slab.json";
    try {
        load_scene(scene_file, {R"(tools+={"name": "t", "device": {"type": "phantom"}})"});
        ADD_FAILURE() << "an unknown device type was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("tools[1].device.type"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("igtl"), std::string::npos) << "the message lists the choices: " << e.what();
    }
    EXPECT_THROW(load_scene(scene_file, {R"(tools+={"name": "t", "device": {"type": "igtl", "port": 70000}})"}),
                 InputError);
    EXPECT_THROW(load_scene(scene_file, {R"(tools+={"name": "t"})"}), InputError) << "a scripted tool needs a trajectory";
    EXPECT_THROW(load_scene(scene_file, {R"(name+=1)"}), InputError) << "+= on a field that is not an array";
    const Scene s = load_scene(scene_file, {R"(tools+={"name": "t", "device": {"type": "igtl", "units": "m"}})"});
    EXPECT_EQ(s.devices[1].units, 1.0);
    EXPECT_EQ(s.devices[1].port, 18944);
    EXPECT_EQ(s.tools.trajectory[1].size(), 1u) << "a live tool without a trajectory holds at the origin";
}

}  // namespace
}  // namespace xcut
