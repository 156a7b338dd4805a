#pragma once
// The haptic loop (paper §4.2): a thread of its own at 1 kHz, while the physics steps at its own
// rate on the other core. Each step the physics publishes, per tool, the latest contact
// linearization: the tissue's reaction F0 and torque at the tool's position x0, and the contact
// stiffness K = sum k n n^T of that tool's contacts. Each tick the loop reads the device's pose x
// and renders, through a virtual coupling of stiffness k_c in series with the contacts,
//     F = F0 - K_eff (x - x0),   K_eff = K (K + k_c I)^-1 k_c,
// so the felt stiffness never exceeds k_c (what the device can render stably) and the force
// follows the hand between physics steps. Rate and jitter are measured, never asserted.
#include <Eigen/Core>
#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/devices/device.h"

namespace xcut {

struct ContactLinearization {
    double time = 0.0;                                    ///< simulated time of the step [s]
    Vec3 position = Vec3::Zero();                         ///< tool position x0 [m]
    Vec3 force = Vec3::Zero();                            ///< reaction on the tool F0 [N]
    Vec3 torque = Vec3::Zero();                           ///< about x0 [N m]
    Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();  ///< K [N/m]
};

/// Tool i's linearization from this step's contacts and reaction.
ContactLinearization linearize_contacts(const World& world, int tool);
/// The force rendered at device position x through a coupling of stiffness k_c [N/m].
Vec3 coupled_force(const ContactLinearization& l, const Vec3& x, double coupling_stiffness);

struct HapticStats {
    long ticks = 0;
    double seconds = 0.0;        ///< wall time the loop ran [s]
    double rate_hz = 0.0;        ///< ticks per second achieved
    double period_p50_ms = 0.0;  ///< tick-to-tick period percentiles [ms]
    double period_p99_ms = 0.0;
    double period_max_ms = 0.0;
};

class HapticLoop {
public:
    /// `devices`: one per tool (not owned); `rate_hz`: target tick rate; `coupling`: k_c [N/m].
    HapticLoop(std::vector<ToolDevice*> devices, double rate_hz = 1000.0, double coupling = 1000.0);
    ~HapticLoop();
    void start();
    void stop();
    /// Called by the physics after each step.
    void publish(const World& world);
    HapticStats stats() const;

private:
    void run();
    std::vector<ToolDevice*> devices_;
    double rate_hz_, coupling_;
    mutable std::mutex mutex_;
    std::vector<ContactLinearization> latest_;
    std::vector<double> periods_ms_;
    double seconds_ = 0.0;
    std::atomic<bool> running_{false};
    std::thread thread_;
};

}  // namespace xcut
