#include "tools/viewer/physics_thread.h"

#include <chrono>
#include <exception>

#include "engine/parallel.h"

namespace xcut::viewer {

PhysicsThread::PhysicsThread(Simulation& sim, SnapshotBuffer& buffer) : sim_(sim), buffer_(buffer) {}

PhysicsThread::~PhysicsThread() { stop(); }

void PhysicsThread::start() {
    take_snapshot(sim_.world, options_, buffer_.back());
    buffer_.publish();
    thread_ = std::thread([this] { run(); });
}

void PhysicsThread::stop() {
    quit_ = true;
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void PhysicsThread::play(bool on) {
    // Play at the step limit (the scene's duration) is the user telling it to go on.
    if (on && step_limit_ >= 0 && steps_done_ >= step_limit_) step_limit_ = -1;
    playing_ = on;
    wake_.notify_all();
}

void PhysicsThread::single_step() {
    ++step_requests_;
    wake_.notify_all();
}

void PhysicsThread::allow_steps(int n) {
    allowed_ += n;
    wake_.notify_all();
}

void PhysicsThread::set_options(const SnapshotOptions& o) {
    std::lock_guard<std::mutex> lock(mutex_);
    options_ = o;
}

std::string PhysicsThread::error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return error_;
}

bool PhysicsThread::idle() const {
    if (failed_) return true;
    if (stepping_) return false;
    if (lockstep_) return allowed_ == 0;
    const bool at_limit = step_limit_ >= 0 && steps_done_ >= step_limit_;
    return step_requests_ == 0 && (!playing_ || at_limit);
}

bool PhysicsThread::may_step() {
    stepping_ = true;  // from the decision on: idle() must not see the allowance spent before the step is done
    const bool step = decide_step();
    stepping_ = step;
    return step;
}

bool PhysicsThread::decide_step() {
    if (lockstep_) {
        if (allowed_ <= 0) return false;
        --allowed_;
        return true;
    }
    if (step_requests_ > 0) {
        --step_requests_;
        return true;
    }
    return playing_ && !(step_limit_ >= 0 && steps_done_ >= step_limit_);
}

std::vector<StepTiming> PhysicsThread::timings() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return timings_;
}

void PhysicsThread::step_once() {
    SolverSettings& s = sim_.world.solver;
    if (dt_request_ > 0.0 && !s.realtime) s.dt = dt_request_.exchange(0.0);
    const int cuts = sim_.world.cuts.count();
    step_simulation(sim_);
    const double t1 = wall_seconds();
    ++steps_done_;
    SnapshotOptions options;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        options = options_;
    }
    Snapshot& snap = buffer_.back();
    take_snapshot(sim_.world, options, snap);
    history_.emplace_back(t1, sim_.world.time);
    while (history_.size() > 2 && history_.back().first - history_.front().first > 1.0) history_.pop_front();
    const double wall = history_.back().first - history_.front().first;
    snap.realtime_factor = wall > 0.0 ? (history_.back().second - history_.front().second) / wall : 0.0;
    buffer_.publish();
    if (keep_timings_) {
        std::lock_guard<std::mutex> lock(mutex_);
        timings_.push_back({wall_seconds(), sim_.world.metrics.current.step_ms, sim_.world.cuts.count() - cuts});
    }
}

void PhysicsThread::run() {
    double pace_wall = 0.0, pace_sim = 0.0;  // where pacing (re)started: set at the first step after a pause
    bool was_stepping = false;
    while (!quit_) {
        if (!may_step()) {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait_for(lock, std::chrono::milliseconds(5));
            was_stepping = false;
            continue;
        }
        if (!was_stepping) pace_wall = wall_seconds(), pace_sim = sim_.world.time;
        was_stepping = true;
        try {
            step_once();
            stepping_ = false;
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(mutex_);
            error_ = e.what();
            failed_ = true;
            stepping_ = false;
            return;
        }
        if (paced_ && !lockstep_) {  // keep simulated time to the wall clock: never run ahead of it
            const double ahead = (sim_.world.time - pace_sim) - (wall_seconds() - pace_wall);
            if (ahead > 0.0) {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait_for(lock, std::chrono::duration<double>(ahead), [this] { return quit_.load(); });
            }
        }
    }
}

}  // namespace xcut::viewer
