#include "engine/parallel.h"

namespace xcut {
namespace {
int g_threads = 2;
}

void set_thread_count(int threads) { g_threads = std::max(1, threads); }
int thread_count() { return g_threads; }

}  // namespace xcut
