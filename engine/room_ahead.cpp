#include "engine/room_ahead.h"

#include <atomic>
#include <cstdint>
#include <sys/mman.h>
#include <unistd.h>

#include "engine/background_threads.h"

namespace xcut {
namespace {

#ifndef MADV_POPULATE_WRITE
constexpr int MADV_POPULATE_WRITE = 23;  // linux/mman.h, Linux 5.14
#endif

std::atomic<long> g_populated{0};

/// Faults in the pages that hold [from, from + bytes); false where the kernel refuses.
bool populate(const char* from, size_t bytes) {
    const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
    const uintptr_t begin = reinterpret_cast<uintptr_t>(from) & ~(page - 1);
    const uintptr_t end = (reinterpret_cast<uintptr_t>(from) + bytes + page - 1) & ~(page - 1);
    if (end <= begin) return false;
    const bool ok = madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE) == 0;
    if (ok) g_populated += static_cast<long>((end - begin) / page);
    return ok;
}

}  // namespace

void populate_in_background(std::vector<RoomStretch> stretches) {
    if (stretches.empty()) return;
    post_background_job([stretches = std::move(stretches)] {
        for (const RoomStretch& s : stretches) populate(s.from, s.bytes);
    });
}

long populated_pages() { return g_populated.load(); }

}  // namespace xcut
