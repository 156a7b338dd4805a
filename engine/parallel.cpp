#include "engine/parallel.h"

#include <chrono>

namespace xcut {
namespace {
int g_threads = 2;
}

void set_thread_count(int threads) { g_threads = std::max(1, threads); }
int thread_count() { return g_threads; }

double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace xcut
