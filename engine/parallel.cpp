#include "engine/parallel.h"

#include <chrono>

#include "engine/background_threads.h"

namespace xcut {
namespace {
int g_threads = 2;
}  // namespace

void set_thread_count(int threads) { g_threads = std::max(1, threads); }
// One thread fewer while a background job runs (engine/background_threads.h).
int thread_count() { return std::max(1, g_threads - background_jobs_running()); }
int configured_thread_count() { return g_threads; }

double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace xcut
