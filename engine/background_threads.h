#pragma once
// Work the engine does off the step (a preconditioner renewed in the background:
// systems/solver/factor_background.h, systems/solver/amg_background.h) runs on one background
// thread per process, started on first use, its jobs in the order they were posted (a job that
// frees a retired factor gives its pages back there too, not in the step).
//  - While a job runs, thread_count() is one fewer (never fewer than one), so the step's OpenMP
//    teams and the job do not contend for the cores: on two cores a team one of whose threads is
//    preempted waits at every barrier (the default skin's steps took 3-6x their median beside a
//    simplicial background factor and a two-thread team; docs/BENCHMARKS.md, cutstep).
// Results do not change: every parallel loop and reduction gives the same bits for any thread
// count (engine/parallel.h), and a job's result is taken at a fixed step.
#include <functional>
#include <future>
#include <memory>

namespace xcut {

/// Posts `job` to the background thread; one of the systems' threads is reserved until it ends.
void post_background_job(std::function<void()> job);

/// Runs `job` on the background thread; its result (or exception) comes through the future.
template <class T>
std::future<T> run_in_background(std::function<T()> job) {
    auto task = std::make_shared<std::packaged_task<T()>>(std::move(job));
    std::future<T> result = task->get_future();
    post_background_job([task] { (*task)(); });
    return result;
}

/// The count of jobs posted and not yet ended (engine/parallel.cpp's thread_count() subtracts it).
int background_jobs_running();

}  // namespace xcut
