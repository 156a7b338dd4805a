#pragma once
// Tool devices: where a tool's pose comes from and where its feedback force goes (paper §4.2).
// `ToolDevice` is the interface a real haptic device (a Phantom, a Virtuose, ...) implements: the
// physics asks it for the tool's pose at a simulated time, and the haptic loop (engine/devices/haptic_loop.h)
// sends it the force to render at 1 kHz. Two implementations here:
//  - ScriptedDevice: the scene's keyframes (or trajectory_csv), interpolated;
//  - ReplayDevice: a session recorded by SessionRecorder, one CSV per tool, replayed exactly: each
//    step asks for the pose at a recorded time and gets the recorded bits back, so a replay with the
//    same thread count is bit-identical to the run that was recorded.
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "components/tools.h"
#include "engine/devices/device_spec.h"
#include "engine/world.h"

namespace xcut {

class ToolDevice {
public:
    virtual ~ToolDevice() = default;
    /// The tool's pose (tool frame -> world) at simulated time t [s].
    virtual Keyframe pose(double t) = 0;
    /// The pose the haptic loop couples to at its tick (haptic thread): the physics' pose at t for a
    /// scripted device, the newest one for a live device (engine/devices/live_device.h).
    virtual Keyframe haptic_pose(double t) { return pose(t); }
    /// A device that renders force to a person (a network haptic device) wants the haptic loop run
    /// even when the command line did not ask for it.
    virtual bool wants_force() const { return false; }
    /// The force and torque the user should feel [N, N m]; called from the haptic thread.
    virtual void render_force(const Vec3& force, const Vec3& torque) = 0;
    virtual const char* kind() const = 0;
};

/// A device that keeps the last force rendered to it, for whoever reads it (tests, the viewer).
class ForceKeepingDevice : public ToolDevice {
public:
    void render_force(const Vec3& force, const Vec3& torque) override;
    Vec3 last_force() const;

private:
    mutable std::mutex force_mutex_;  ///< the haptic thread writes the force, others read it
    Vec3 force_ = Vec3::Zero(), torque_ = Vec3::Zero();
};

/// Keyframes, interpolated (linear position, slerp orientation); the rendered force is kept.
class ScriptedDevice : public ForceKeepingDevice {
public:
    explicit ScriptedDevice(std::vector<Keyframe> keys, const char* kind = "scripted")
        : keys_(std::move(keys)), kind_(kind) {}
    Keyframe pose(double t) override;
    const char* kind() const override { return kind_; }

private:
    std::vector<Keyframe> keys_;
    const char* kind_;
};

/// A recorded session: the poses a run's tools had at each step (SessionRecorder's files).
std::unique_ptr<ToolDevice> make_replay_device(const std::string& directory, const std::string& tool);

/// Makes the device of a tool whose "device" field names a type other than "scripted"; `start` is
/// the tool's first keyframe (where it holds until the device says otherwise).
using DeviceFactory = std::function<std::unique_ptr<ToolDevice>(const DeviceSpec& spec, const std::string& tool,
                                                                const Keyframe& start)>;
/// The front end registers the device types it was built with ("igtl"); a scene naming a type no
/// factory makes is an InputError naming the field.
void register_device_type(const std::string& type, DeviceFactory factory);

/// Devices for every tool of `world`: its scene `specs` (scripted from its trajectory unless the
/// spec names another type), or, when `replay_directory` is given, replayed from
/// `<replay_directory>/<tool name>.csv`.
std::vector<std::unique_ptr<ToolDevice>> make_devices(const World& world, const std::vector<DeviceSpec>& specs,
                                                      const std::string& replay_directory);

/// What a session ran: its scene file and the --set overrides it was loaded with (the viewer's own
/// tools among them), written to `<directory>/session.json` so `--replay` rebuilds the same scene.
struct SessionInfo {
    std::string scene;
    std::vector<std::string> overrides;
};
/// The overrides of a recorded session (empty when it has no session.json).
std::vector<std::string> read_session_overrides(const std::string& directory);

/// Writes every pose each tool's device gave to `<directory>/<tool name>.csv` (the trajectory_csv
/// format, 17 significant digits: the doubles read back exactly), the sub-step samples of a blade's
/// sweep (ToolBodies::sweep) included, and each step's dt to `<directory>/steps.csv`, so a session
/// in real-time mode, whose dt follows the wall clock, replays on the same time axis.
class SessionRecorder {
public:
    /// Opens the files, writes session.json and records the tools' initial poses.
    SessionRecorder(const World& world, const std::string& directory, const SessionInfo& info = {});
    /// After a step: the poses of the step and the dt it took.
    void record(const World& world);

private:
    void write_pose(int tool, const Keyframe& k);
    std::vector<std::ofstream> files_;
    std::ofstream steps_;
    int step_ = 0;
};

/// The dt of every step of a recorded session (`<directory>/steps.csv`) [s]; empty when the session
/// has no such file (recorded before it existed: it replays at the scene's own dt).
std::vector<double> read_session_steps(const std::string& directory);

}  // namespace xcut
