#pragma once
// A tool moved by an OpenIGTLink peer: a tracker, a haptic device, 3D Slicer (OpenIGTLink protocol
// version 2, Debian's libopenigtlink). The tool's "device": {"type": "igtl", ...} field
// (engine/devices/device_spec.h) says where to listen or connect.
//  - Poses: TRANSFORM messages (a 4x4 matrix: rotation, translation in the device's units) and
//    POSITION messages (position and quaternion), from the stream named `stream` or any. Each pose
//    becomes the tool's target (engine/devices/live_device.h): the tool moves there by the end of
//    the next step.
//  - Feedback: after each haptic tick, an NDARRAY message named "<tool>_force", 6 float64 values:
//    the force [N] and torque [N m] the haptic loop renders (engine/devices/haptic_loop.h), sent at
//    most at `force_rate` per second.
//  - `sync`: a replayed stream, stamped with simulated time (the message's time stamp, 2^-32 s
//    resolution): each step waits until a pose stamped at or after its time has arrived, and the
//    poses are interpolated as a scripted trajectory's; a run then gives the same bits as the same
//    keyframes read from CSV.
//  - Failures never stop the simulation: a malformed message (bad CRC, unknown size, a body over
//    1 MB) or a lost connection holds the tool where it is, prints one warning line for the first
//    time and counts the rest, and the device waits for the peer to connect again.
#include <atomic>
#include <condition_variable>
#include <string>
#include <thread>
#include <vector>

#include "engine/devices/device_spec.h"
#include "engine/devices/live_device.h"

namespace xcut {

struct IgtlStats {
    long poses = 0;        ///< TRANSFORM / POSITION messages taken
    long ignored = 0;      ///< well-formed messages of other types or streams, skipped
    long malformed = 0;    ///< messages dropped as malformed
    long connections = 0;  ///< peers that connected
    long lost = 0;         ///< connections that ended or broke
    long timeouts = 0;     ///< sync: steps that waited `timeout` for a pose in vain
    long forces_sent = 0;  ///< NDARRAY force messages sent
};

class IgtlDevice : public LiveDevice {
public:
    /// Listens (host empty) or connects; throws InputError naming the scene field if it cannot listen.
    IgtlDevice(const DeviceSpec& spec, const std::string& tool, const Keyframe& start);
    ~IgtlDevice() override;
    Keyframe pose(double t) override;
    void render_force(const Vec3& force, const Vec3& torque) override;
    bool wants_force() const override { return true; }
    IgtlStats stats() const;

    static constexpr double force_rate = 1000.0;  ///< most force messages a second [Hz]

private:
    void serve();
    bool read_fully(int fd, void* data, size_t size);
    void take_pose(const Keyframe& k);
    void warn(const std::string& what, long& counter);

    DeviceSpec spec_;
    std::string tool_;
    std::atomic<bool> quit_{false};
    std::atomic<int> peer_{-1};  ///< the connected socket, -1 none
    int listener_ = -1;
    std::thread thread_;
    std::condition_variable arrived_;
    std::vector<Keyframe> received_;  ///< sync: poses by time stamp
    bool stream_ended_ = false;       ///< sync: the peer left after its last pose
    IgtlStats stats_;
    std::mutex send_mutex_;
    double last_send_ = 0.0;          ///< wall time of the last force message [s]
};

/// Registers "igtl" with make_devices (engine/devices/device.h).
void register_igtl_device();

}  // namespace xcut
