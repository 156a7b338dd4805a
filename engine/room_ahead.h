#pragma once
// Pages of reserved room made resident before the step writes them. A split appends its virtual
// elements and phantoms into room reserved at load (prepare_enrichment), and the first write to a
// fresh page faults. With malloc's transparent huge pages (engine/startup_environment.h) that fault is a 2 MiB
// page, and under the kernel's `defrag` setting `madvise` it may wait for the kernel to compact
// memory first: in 11 of 24 full runs of the cut benchmark one step of the 200k-tet rows took
// 2.5-23 ms, their other steps 0.6-1.4 ms (docs/BENCHMARKS.md, Cut update). So ahead of the splits
// the next stretch of each array's room is faulted in on the background thread
// (engine/background_threads.h), MADV_POPULATE_WRITE (Linux 5.14): the kernel maps the pages
// writable without writing them, so the step's own writes to the same pages, before or after, are
// unaffected, and so are the results. A kernel without it refuses the advice, and the step's first
// write faults as before.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace xcut {

/// A stretch of an array's reserved room, past its last element.
struct RoomStretch {
    const char* from;
    size_t bytes;
};

/// The room past v's last element, at most `count` elements of it (none if v has no room left).
template <class V>
void add_room_ahead(const V& v, size_t count, std::vector<RoomStretch>& out) {
    const size_t n = std::min(v.capacity() - v.size(), count);
    if (n > 0) out.push_back({reinterpret_cast<const char*>(v.data() + v.size()), n * sizeof(typename V::value_type)});
}

/// Faults the stretches' pages in on the background thread (a stretch whose array has since moved
/// is advice on memory that is no longer its: the kernel refuses it or maps pages that another use
/// then finds mapped, neither changing a byte).
void populate_in_background(std::vector<RoomStretch> stretches);

/// The page-aligned addresses [first, second) of the pages that hold [from, from + bytes).
std::pair<uintptr_t, uintptr_t> pages_holding(const char* from, size_t bytes);

}  // namespace xcut
