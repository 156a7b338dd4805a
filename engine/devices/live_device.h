#pragma once
// A tool device moved live by another thread: the viewer's mouse and keys, a tracker over the
// network. The other thread sets a target pose whenever it has one; the physics takes the targets
// given since its last step at the end of the next one and sees the tool move along the path they
// make (straight between them, slerp for the orientation), spaced evenly over the step so that the
// same calls give the same path whatever the timing, as a Python controller's must. A blade
// sampled inside the step (ToolBodies::sweep) sweeps the way the hand went and cuts what it passed,
// even when the physics is slower than the hand: a press, a drag and a release given within one
// step still cut (only the newest target was kept before, and a quick drag in a viewer slowed by a
// busy machine cut nothing). Every pose given to the physics lands in a recorded session
// (SessionRecorder), so a live session replays bit for bit.
#include <mutex>
#include <vector>

#include "engine/devices/device.h"

namespace xcut {

class LiveDevice : public ForceKeepingDevice {
public:
    LiveDevice(const Keyframe& start, const char* kind);
    /// Follows `script` (the tool's scripted trajectory) until take_over() is called.
    LiveDevice(std::vector<Keyframe> script, const char* kind);
    /// From the next step on, the tool follows the targets, starting where the script left it.
    void take_over();
    bool live() const;
    /// Any thread: the pose the tool should go to [m, tool -> world].
    void set_target(const Vec3& position, const Eigen::Quaterniond& orientation);
    Keyframe target() const;
    /// Physics thread. A time past the last one given takes the newest target as the end of a new
    /// segment; an earlier time interpolates on the current segment.
    Keyframe pose(double t) override;
    /// Haptic thread: the newest target, where the hand is now.
    Keyframe haptic_pose(double t) override;
    const char* kind() const override { return kind_; }

protected:
    /// With mutex_ held: set_target() and target() for a subclass that holds the lock already.
    void set_target_locked(const Vec3& position, const Eigen::Quaterniond& orientation);
    Keyframe target_locked() const { return target_; }
    mutable std::mutex mutex_;

private:
    const char* kind_;
    Keyframe target_, from_, to_;  ///< newest target; the current step's start and end
    /// The targets given since the last step began; `path_` is the current step's: from_, then
    /// them, in simulated time.
    std::vector<Keyframe> given_, path_;
    std::vector<Keyframe> script_;  ///< followed while not live
    bool live_ = true, take_over_ = false, started_ = false;
};


}  // namespace xcut
