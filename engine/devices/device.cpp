#include "engine/devices/device.h"

#include "engine/trajectory.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>

#include <map>
#include <nlohmann/json.hpp>

#include "engine/error.h"
#include "engine/io/scene.h"

namespace xcut {

Keyframe ScriptedDevice::pose(double t) { return sample_trajectory(keys_, t); }

void ForceKeepingDevice::render_force(const Vec3& force, const Vec3& torque) {
    std::lock_guard<std::mutex> lock(force_mutex_);
    force_ = force, torque_ = torque;
}

Vec3 ForceKeepingDevice::last_force() const {
    std::lock_guard<std::mutex> lock(force_mutex_);
    return force_;
}

std::unique_ptr<ToolDevice> make_replay_device(const std::string& directory, const std::string& tool) {
    return std::make_unique<ScriptedDevice>(read_trajectory_csv(directory + "/" + tool + ".csv"), "replay");
}

namespace {

std::map<std::string, DeviceFactory>& device_types() {
    static std::map<std::string, DeviceFactory> types;
    return types;
}

}  // namespace

void register_device_type(const std::string& type, DeviceFactory factory) { device_types()[type] = std::move(factory); }

std::vector<std::unique_ptr<ToolDevice>> make_devices(const World& world, const std::vector<DeviceSpec>& specs,
                                                      const std::string& replay_directory) {
    std::vector<std::unique_ptr<ToolDevice>> devices;
    for (int i = 0; i < world.tools.count(); ++i) {
        const DeviceSpec spec = i < static_cast<int>(specs.size()) ? specs[i] : DeviceSpec{};
        if (!replay_directory.empty()) {
            devices.push_back(make_replay_device(replay_directory, world.tools.name[i]));
        } else if (spec.type == "scripted") {
            devices.push_back(std::make_unique<ScriptedDevice>(world.tools.trajectory[i]));
        } else {
            const auto f = device_types().find(spec.type);
            if (f == device_types().end())
                throw InputError(spec.file, spec.field + ".type",
                                 fmt::format("\"{}\": this build of xcut has no such device (built without it?)", spec.type));
            devices.push_back(f->second(spec, world.tools.name[i], world.tools.trajectory[i].front()));
        }
    }
    return devices;
}

std::vector<std::string> read_session_overrides(const std::string& directory) {
    const std::string path = directory + "/session.json";
    std::ifstream in(path);
    std::vector<std::string> out;
    if (!in) return out;
    nlohmann::json j;
    try {
        in >> j;
        for (const auto& o : j.at("overrides")) out.push_back(o.get<std::string>());
    } catch (const nlohmann::json::exception& e) {
        throw InputError(path, "overrides", std::string("expected {\"overrides\": [\"field=value\", ...]}: ") + e.what());
    }
    return out;
}

namespace {

/// Tool i's current pose, at the world's time.
Keyframe current_pose(const World& world, int i) {
    Keyframe k;
    k.time = world.time, k.position = world.tools.position[i], k.orientation = world.tools.orientation[i];
    return k;
}

}  // namespace

SessionRecorder::SessionRecorder(const World& world, const std::string& directory, const SessionInfo& info) {
    std::error_code ec;
    std::filesystem::create_directories(directory, ec);
    if (ec) throw InputError(directory, "--record", "cannot create the directory: " + ec.message());
    std::ofstream session(directory + "/session.json");
    if (!session) throw InputError(directory + "/session.json", "--record", "cannot write the session file");
    session << nlohmann::json{{"scene", info.scene}, {"overrides", info.overrides}}.dump(2) << "\n";
    for (const std::string& name : world.tools.name) {
        const std::string path = directory + "/" + name + ".csv";
        files_.emplace_back(path);
        if (!files_.back()) throw InputError(path, "--record", "cannot write the session file");
        files_.back() << "time,x,y,z,qw,qx,qy,qz\n";
    }
    steps_.open(directory + "/steps.csv");
    if (!steps_) throw InputError(directory + "/steps.csv", "--record", "cannot write the session file");
    steps_ << "step,dt_s\n";
    for (int i = 0; i < world.tools.count(); ++i) write_pose(i, current_pose(world, i));
    for (auto& f : files_) f.flush();
}

void SessionRecorder::write_pose(int i, const Keyframe& k) {
    const Vec3& p = k.position;
    const Eigen::Quaterniond& q = k.orientation;
    files_[i] << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", k.time, p.x(), p.y(),
                             p.z(), q.w(), q.x(), q.y(), q.z());
}

void SessionRecorder::record(const World& world) {
    const ToolBodies& tb = world.tools;
    for (int i = 0; i < tb.count(); ++i) {
        if (i < static_cast<int>(tb.sweep.size()) && tb.sweep[i].size() > 1) {
            // Every pose the device gave over the step; the first is the last step's end.
            for (size_t k = 1; k < tb.sweep[i].size(); ++k) write_pose(i, tb.sweep[i][k]);
        } else {
            write_pose(i, current_pose(world, i));
        }
    }
    steps_ << fmt::format("{},{:.17g}\n", ++step_, world.solver.dt);
    for (auto& f : files_) f.flush();
    steps_.flush();
}

std::vector<double> read_session_steps(const std::string& directory) {
    const std::string path = directory + "/steps.csv";
    std::ifstream in(path);
    std::vector<double> dts;
    if (!in) return dts;
    std::string line;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
        if (line_no == 1 && line.rfind("step", 0) == 0) continue;
        if (line.empty()) continue;
        const size_t comma = line.find(',');
        char* end = nullptr;
        const double dt = comma == std::string::npos ? 0.0 : std::strtod(line.c_str() + comma + 1, &end);
        if (comma == std::string::npos || end == line.c_str() + comma + 1 || !(dt > 0.0) || !std::isfinite(dt))
            throw InputError(path, fmt::format("line {}", line_no), "expected step,dt_s with a positive, finite dt");
        dts.push_back(dt);
    }
    return dts;
}

}  // namespace xcut
