// The threads a team takes (engine/parallel.h): one fewer while a background job runs, the
// configured count unchanged, so what saves and restores the setting keeps it.
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>

#include "engine/background_threads.h"
#include "engine/parallel.h"

namespace xcut {
namespace {

TEST(ThreadCount, ABackgroundJobTakesOneThreadFromTheTeamsNotFromTheSetting) {
    const int kept = configured_thread_count();
    set_thread_count(2);
    std::promise<void> release;
    std::shared_future<void> released = release.get_future().share();
    std::promise<void> started;
    post_background_job([&started, released] {
        started.set_value();
        released.wait();
    });
    started.get_future().wait();
    EXPECT_EQ(thread_count(), 1) << "a team beside the job takes one thread";
    EXPECT_EQ(configured_thread_count(), 2) << "the setting is what --threads said";
    set_thread_count(configured_thread_count());  // a save and restore while the job runs
    EXPECT_EQ(configured_thread_count(), 2) << "restored to the setting, not to the momentary team";
    release.set_value();
    // The job's count drops just after it returns: wait for it (bounded; it is the next thing the
    // background thread does).
    for (int i = 0; i < 30000 && background_jobs_running() > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_EQ(background_jobs_running(), 0);
    EXPECT_EQ(thread_count(), 2) << "the team has both threads again";
    set_thread_count(kept);
}

}  // namespace
}  // namespace xcut
