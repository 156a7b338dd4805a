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

namespace {
constexpr size_t kMaxGiven = 512;  // targets kept between two steps; past it every other one goes
}

void LiveDevice::set_target_locked(const Vec3& position, const Eigen::Quaterniond& orientation) {
    target_.position = position;
    target_.orientation = orientation.normalized();
    if (given_.size() >= kMaxGiven) {  // a stalled physics: keep the path's shape, half the points
        for (size_t k = 1; 2 * k < given_.size(); ++k) given_[k] = given_[2 * k];
        given_.resize(given_.size() / 2);
    }
    given_.push_back(target_);
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
        given_.clear();
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
        // The path: from_, then the targets given since, evenly over the step (the newest, to_, at
        // its end).
        path_.assign(1, from_);
        const double n = static_cast<double>(given_.size());
        for (size_t k = 0; k + 1 < given_.size(); ++k) {
            Keyframe p = given_[k];
            p.time = from_.time + (static_cast<double>(k) + 1.0) / n * (t - from_.time);
            if (p.time > path_.back().time) path_.push_back(p);
        }
        path_.push_back(to_);
        given_.clear();
    }
    for (size_t k = 1; k < path_.size(); ++k)
        if (t <= path_[k].time) return interpolate_pose(path_[k - 1], path_[k], t);
    return to_;
}

Keyframe LiveDevice::haptic_pose(double t) {
    std::lock_guard<std::mutex> lock(mutex_);
    Keyframe k = target_;
    k.time = t;
    return k;
}


}  // namespace xcut
