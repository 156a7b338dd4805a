#include "engine/devices/haptic_loop.h"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>

namespace xcut {

ContactLinearization linearize_contacts(const World& w, int tool) {
    ContactLinearization l;
    const ToolBodies& tb = w.tools;
    l.time = w.time;
    l.position = tb.position[tool];
    if (tool < static_cast<int>(tb.reaction_force.size())) l.force = tb.reaction_force[tool], l.torque = tb.reaction_torque[tool];
    const Contacts& c = w.contacts;
    for (int k = 0; k < c.count(); ++k)
        if (c.tool[k] == tool) l.stiffness += c.stiffness[k] * c.normal[k] * c.normal[k].transpose();
    return l;
}

Vec3 coupled_force(const ContactLinearization& l, const Vec3& x, double kc) {
    const Eigen::Matrix3d k_eff = l.stiffness * (l.stiffness + kc * Eigen::Matrix3d::Identity()).inverse() * kc;
    return l.force - k_eff * (x - l.position);
}

HapticLoop::HapticLoop(std::vector<ToolDevice*> devices, double rate_hz, double coupling)
    : devices_(std::move(devices)), rate_hz_(rate_hz), coupling_(coupling), latest_(devices_.size()) {}

HapticLoop::~HapticLoop() { stop(); }

void HapticLoop::start() {
    if (running_.exchange(true)) return;
    periods_ms_.clear();
    periods_ms_.reserve(1 << 20);
    thread_ = std::thread([this] { run(); });
}

void HapticLoop::stop() {
    if (!running_.exchange(false)) return;
    thread_.join();
}

void HapticLoop::publish(const World& world) {
    std::vector<ContactLinearization> next(devices_.size());
    for (size_t i = 0; i < devices_.size(); ++i) next[i] = linearize_contacts(world, static_cast<int>(i));
    std::lock_guard<std::mutex> lock(mutex_);
    latest_.swap(next);
}

void HapticLoop::run() {
    using clock = std::chrono::steady_clock;
    const auto period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(1.0 / rate_hz_));
    const auto start = clock::now();
    auto next = start, last = start;
    std::vector<ContactLinearization> lin;
    while (running_.load(std::memory_order_relaxed)) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            lin = latest_;
        }
        for (size_t i = 0; i < devices_.size(); ++i) {
            const Keyframe pose = devices_[i]->haptic_pose(lin[i].time);
            devices_[i]->render_force(coupled_force(lin[i], pose.position, coupling_), lin[i].torque);
        }
        next += period;
        std::this_thread::sleep_until(next);
        const auto now = clock::now();
        if (periods_ms_.size() < periods_ms_.capacity())
            periods_ms_.push_back(std::chrono::duration<double, std::milli>(now - last).count());
        last = now;
    }
    seconds_ = std::chrono::duration<double>(clock::now() - start).count();
}

HapticStats HapticLoop::stats() const {
    HapticStats s;
    if (running_) return s;  // read once stopped
    std::vector<double> p = periods_ms_;
    s.ticks = static_cast<long>(p.size());
    s.seconds = seconds_;
    if (p.empty()) return s;
    s.rate_hz = s.ticks / std::max(seconds_, 1e-9);
    std::sort(p.begin(), p.end());
    s.period_p50_ms = p[p.size() / 2];
    s.period_p99_ms = p[std::min(p.size() - 1, p.size() * 99 / 100)];
    s.period_max_ms = p.back();
    return s;
}

}  // namespace xcut
