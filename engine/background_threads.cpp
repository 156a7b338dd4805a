#include "engine/background_threads.h"

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

namespace xcut {
namespace {

std::atomic<int> g_running{0};

/// The process's background thread and its queue; joined at exit after its last job.
class BackgroundThread {
public:
    BackgroundThread() : thread_([this] { run(); }) {}
    ~BackgroundThread() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_one();
        thread_.join();
    }

    void post(std::function<void()> job) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            jobs_.push_back(std::move(job));
        }
        wake_.notify_one();
    }

private:
    void run() {
        for (;;) {
            std::function<void()> job;
            {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
                if (jobs_.empty()) return;
                job = std::move(jobs_.front());
                jobs_.pop_front();
            }
            job();  // a packaged task: its exceptions go to its future
            g_running.fetch_sub(1, std::memory_order_relaxed);
        }
    }

    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> jobs_;
    bool stop_ = false;
    std::thread thread_;  // last: started once the members it uses exist
};

}  // namespace

void post_background_job(std::function<void()> job) {
    static BackgroundThread background;
    g_running.fetch_add(1, std::memory_order_relaxed);
    background.post(std::move(job));
}

int background_jobs_running() { return g_running.load(std::memory_order_relaxed); }

}  // namespace xcut
