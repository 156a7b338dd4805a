#pragma once
// The physics on a thread of its own: it steps the simulation and, after each step, copies a
// snapshot into the triple buffer the window draws from (tools/viewer/snapshot.h). The window only
// sets what the thread reads at its next step boundary (play, pause, single step, dt, pacing,
// overlays); it never waits for a step, and a step never waits for a frame.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/simulation.h"
#include "tools/viewer/snapshot.h"

namespace xcut::viewer {

/// One step as the timing log keeps it (`xcut view --timing-csv`, tools/viewer/viewer_timing.h).
struct StepTiming {
    double wall_end = 0.0;  ///< when the step was published [s] (wall_seconds)
    double step_ms = 0.0;   ///< the step's own wall time [ms]
    int split = 0;          ///< elements it split
};

class PhysicsThread {
public:
    PhysicsThread(Simulation& sim, SnapshotBuffer& buffer);
    ~PhysicsThread();
    void start();
    void stop();

    void play(bool on);
    bool playing() const { return playing_; }
    void single_step();
    /// Paced: the simulated time keeps to the wall clock (never ahead of it); unpaced: as fast as it can.
    void set_paced(bool on) { paced_ = on; }
    bool paced() const { return paced_; }
    /// Lockstep: steps only when allowed (scripted input: one step per frame, reproducible).
    void set_lockstep(bool on) { lockstep_ = on; }
    void allow_steps(int n);
    /// Pauses once this many steps are done (< 0: never); play() past it lifts it.
    void set_step_limit(int steps) { step_limit_ = steps; }
    /// The fixed dt of the next steps [s] (ignored in real-time mode, where dt follows the clock).
    void set_dt(double dt) { dt_request_ = dt; }
    void set_options(const SnapshotOptions& o);

    int steps_done() const { return steps_done_; }
    bool idle() const;                ///< paused, at its limit, or failed
    bool failed() const { return failed_; }
    std::string error() const;        ///< why the physics stopped (an InputError, a NumericalError)
    /// Keeps every step's timing from now on (before start()).
    void keep_timings(bool on) { keep_timings_ = on; }
    std::vector<StepTiming> timings() const;

private:
    void run();
    bool may_step();
    bool decide_step();
    void step_once();
    Simulation& sim_;
    SnapshotBuffer& buffer_;
    std::thread thread_;
    std::atomic<bool> quit_{false}, playing_{true}, paced_{true}, lockstep_{false}, failed_{false}, stepping_{false},
        keep_timings_{false};
    std::atomic<int> step_requests_{0}, allowed_{0}, step_limit_{-1}, steps_done_{0};
    std::atomic<double> dt_request_{0.0};
    mutable std::mutex mutex_;        ///< guards options_, error_ and timings_
    std::condition_variable wake_;
    SnapshotOptions options_;
    std::string error_;
    std::vector<StepTiming> timings_;
    std::deque<std::pair<double, double>> history_;  ///< (wall, simulated) time of recent steps [s]
};

}  // namespace xcut::viewer
