#include "engine/devices/device.h"

#include <filesystem>
#include <fmt/format.h>

#include "engine/error.h"
#include "engine/io/scene.h"

namespace xcut {

Keyframe ScriptedDevice::pose(double t) { return sample_trajectory(keys_, t); }

void ScriptedDevice::render_force(const Vec3& force, const Vec3& torque) {
    std::lock_guard<std::mutex> lock(mutex_);
    force_ = force, torque_ = torque;
}

Vec3 ScriptedDevice::last_force() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return force_;
}

std::unique_ptr<ToolDevice> make_replay_device(const std::string& directory, const std::string& tool) {
    return std::make_unique<ScriptedDevice>(read_trajectory_csv(directory + "/" + tool + ".csv"), "replay");
}

std::vector<std::unique_ptr<ToolDevice>> make_devices(const World& world, const std::string& replay_directory) {
    std::vector<std::unique_ptr<ToolDevice>> devices;
    for (int i = 0; i < world.tools.count(); ++i) {
        if (replay_directory.empty())
            devices.push_back(std::make_unique<ScriptedDevice>(world.tools.trajectory[i]));
        else
            devices.push_back(make_replay_device(replay_directory, world.tools.name[i]));
    }
    return devices;
}

SessionRecorder::SessionRecorder(const World& world, const std::string& directory) {
    std::error_code ec;
    std::filesystem::create_directories(directory, ec);
    if (ec) throw InputError(directory, "--record", "cannot create the directory: " + ec.message());
    for (const std::string& name : world.tools.name) {
        const std::string path = directory + "/" + name + ".csv";
        files_.emplace_back(path);
        if (!files_.back()) throw InputError(path, "--record", "cannot write the session file");
        files_.back() << "time,x,y,z,qw,qx,qy,qz\n";
    }
    record(world);
}

void SessionRecorder::record(const World& world) {
    const ToolBodies& tb = world.tools;
    for (int i = 0; i < tb.count(); ++i) {
        const Vec3& p = tb.position[i];
        const Eigen::Quaterniond& q = tb.orientation[i];
        files_[i] << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", world.time, p.x(),
                                 p.y(), p.z(), q.w(), q.x(), q.y(), q.z());
    }
    for (auto& f : files_) f.flush();
}

}  // namespace xcut
