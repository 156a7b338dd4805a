#include "engine/devices/live_device.h"

#include "engine/trajectory.h"

namespace xcut {

LiveDevice::LiveDevice(const Keyframe& start, const char* kind) : kind_(kind), target_(start), from_(start), to_(start) {}

LiveDevice::LiveDevice(std::vector<Keyframe> script, const char* kind)
    : LiveDevice(script.empty() ? Keyframe{} : script.front(), kind) {
    script_ = std::move(script);
    live_ = script_.empty();
}

void LiveDevice::take_over() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!live_) take_over_ = true;
}

bool LiveDevice::live() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_ || take_over_;
}

void LiveDevice::set_target(const Vec3& position, const Eigen::Quaterniond& orientation) {
    std::lock_guard<std::mutex> lock(mutex_);
    set_target_locked(position, orientation);
}

void LiveDevice::set_target_locked(const Vec3& position, const Eigen::Quaterniond& orientation) {
    target_.position = position;
    target_.orientation = orientation.normalized();
}

Keyframe LiveDevice::target() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return target_;
}

Keyframe LiveDevice::pose(double t) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!live_ && take_over_ && t > to_.time) {  // the hand takes the tool where the script left it
        live_ = true;
        target_ = to_;
    }
    if (!live_) {
        const Keyframe k = sample_trajectory(script_, t);
        if (!started_ || t > to_.time) to_ = k, target_ = k, started_ = true;
        return k;
    }
    if (!started_ || t > to_.time) {
        from_ = started_ ? to_ : target_;
        if (!started_) from_.time = t;
        to_ = target_;
        to_.time = t;
        started_ = true;
    }
    return interpolate_pose(from_, to_, t);
}

Keyframe LiveDevice::haptic_pose(double t) {
    std::lock_guard<std::mutex> lock(mutex_);
    Keyframe k = target_;
    k.time = t;
    return k;
}


}  // namespace xcut
