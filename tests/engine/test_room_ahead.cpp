// The room past an array's end made resident off the step (engine/room_ahead.h): measured by the
// kernel's own residency map (mincore), before and after.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdint>
#include <future>
#include <sys/mman.h>
#include <unistd.h>
#include <vector>

#include "engine/background_threads.h"
#include "engine/room_ahead.h"

namespace xcut {
namespace {

/// How many of the pages that hold [from, from + bytes) are resident.
long resident_pages(const char* from, size_t bytes) {
    const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
    const auto [begin, end] = pages_holding(from, bytes);
    std::vector<unsigned char> map((end - begin) / page);
    if (mincore(reinterpret_cast<void*>(begin), end - begin, map.data()) != 0) return -1;
    long resident = 0;
    for (unsigned char m : map) resident += m & 1;
    return resident;
}

/// Waits until the background thread has run every job posted before (they run in order).
void drain_background() { run_in_background<int>([] { return 0; }).get(); }

TEST(RoomAhead, TheRoomPastAnArraysEndIsMadeResidentOnTheBackgroundThread) {
    // Does this kernel take the advice at all (Linux 5.14)? Asked of a mapping of our own.
    const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    void* probe = mmap(nullptr, page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    ASSERT_NE(probe, MAP_FAILED);
    const bool supported = madvise(probe, page, 23 /* MADV_POPULATE_WRITE */) == 0 || errno != EINVAL;
    munmap(probe, page);
    if (!supported) GTEST_SKIP() << "this kernel has no MADV_POPULATE_WRITE: the step's writes fault as before";

    // 32 MiB of room (malloc maps it fresh, untouched), 1,000 elements in use.
    std::vector<double> v;
    v.reserve(size_t{4} << 20);
    v.assign(1000, 1.0);
    std::vector<RoomStretch> room;
    add_room_ahead(v, 1000000, room);  // 8 MB: more than the huge page the elements in use may sit in
    ASSERT_EQ(room.size(), 1u);
    EXPECT_EQ(room[0].from, reinterpret_cast<const char*>(v.data() + 1000));
    EXPECT_EQ(room[0].bytes, 1000000 * sizeof(double));
    const char* far = reinterpret_cast<const char*>(v.data() + (size_t{3} << 20));  // beyond the stretch
    const long stretch_before = resident_pages(room[0].from, room[0].bytes), far_before = resident_pages(far, page);
    const long pages = static_cast<long>((room[0].bytes + 2 * page - 1) / page);
    ASSERT_GE(stretch_before, 0);
    ASSERT_LT(stretch_before, pages / 2) << "the room was resident before it was asked for";
    populate_in_background(room);
    drain_background();
    EXPECT_GE(resident_pages(room[0].from, room[0].bytes), pages - 1) << "before: " << stretch_before;
    EXPECT_EQ(resident_pages(far, page), far_before);  // only the stretch asked for
    // The elements in use are unchanged, and so is the room's content when written after.
    for (double x : v) ASSERT_EQ(x, 1.0);
    v.resize(2000, 2.0);
    EXPECT_EQ(v[1999], 2.0);

    // No room left: nothing asked.
    std::vector<int> full(10);
    full.shrink_to_fit();
    std::vector<RoomStretch> none;
    add_room_ahead(full, 100, none);
    EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace xcut
