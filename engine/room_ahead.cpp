#include "engine/room_ahead.h"

#include <sys/mman.h>
#include <unistd.h>

#include "engine/background_threads.h"

namespace xcut {
namespace {

#ifndef MADV_POPULATE_WRITE
constexpr int MADV_POPULATE_WRITE = 23;  // linux/mman.h, Linux 5.14
#endif

}  // namespace

std::pair<uintptr_t, uintptr_t> pages_holding(const char* from, size_t bytes) {
    const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
    const auto at = reinterpret_cast<uintptr_t>(from);
    return {at & ~(page - 1), (at + bytes + page - 1) & ~(page - 1)};
}

void populate_in_background(std::vector<RoomStretch> stretches) {
    if (stretches.empty()) return;
    post_background_job([stretches = std::move(stretches)] {
        for (const RoomStretch& s : stretches) {  // a refusal (an old kernel) leaves the first write to fault
            const auto [begin, end] = pages_holding(s.from, s.bytes);
            if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
        }
    });
}

}  // namespace xcut
