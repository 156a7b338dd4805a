#include "systems/solver/cholmod_pages.h"

#include <SuiteSparse_config.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <utility>
#include <vector>

namespace xcut {
namespace {

constexpr size_t kKeptMin = size_t{256} << 10;   ///< blocks from this size are kept when freed [bytes]
/// At most this much is held [bytes]: a retired factor's blocks for its successor. The skin at 1 mm
/// elements (L 4.1 M non-zeros) frees 40 MB of L's values, 20 MB of their single-precision copy and
/// its index arrays at each swap, beside the 21 MB of work arrays held from the factorization.
constexpr size_t kKeptMax = size_t{128} << 20;
/// Room a kept-size block is given beyond its request, so that the next factor's slightly larger
/// arrays (a cut added DOFs) fit in it: an eighth. Pages past the request are not touched.
constexpr size_t kRoomDivisor = 8;

/// Before each block: its capacity and the bytes asked for (realloc copies those). 16 bytes keep
/// the payload at malloc's own alignment.
struct Header {
    size_t capacity, size;
};
static_assert(sizeof(Header) == 16);

// Never destroyed: a factor freed during the process's exit (a simulation a Python interpreter
// drops last) still finds them.
std::mutex& kept_lock() {
    static std::mutex* lock = new std::mutex;
    return *lock;
}

/// Freed blocks held for reuse: (capacity, header), and their total capacity.
std::vector<std::pair<size_t, Header*>>& kept_blocks() {
    static auto* blocks = new std::vector<std::pair<size_t, Header*>>;
    return *blocks;
}
size_t kept_total = 0;

Header* header_of(void* p) { return static_cast<Header*>(p) - 1; }

/// The smallest held block of at least `bytes` and at most twice that, taken out of the cache.
Header* take_kept(size_t bytes) {
    std::lock_guard<std::mutex> lock(kept_lock());
    auto& blocks = kept_blocks();
    auto best = blocks.end();
    for (auto it = blocks.begin(); it != blocks.end(); ++it)
        if (it->first >= bytes && it->first / 2 <= bytes && (best == blocks.end() || it->first < best->first)) best = it;
    if (best == blocks.end()) return nullptr;
    Header* h = best->second;
    kept_total -= best->first;
    blocks.erase(best);
    return h;
}

/// The capacity a new block of `bytes` is given (kept-size blocks with room).
size_t capacity_for(size_t bytes) { return bytes >= kKeptMin ? bytes + bytes / kRoomDivisor : bytes; }

}  // namespace

void* kept_malloc(size_t bytes) {
    bytes = std::max<size_t>(bytes, 1);
    Header* h = bytes >= kKeptMin ? take_kept(bytes) : nullptr;
    if (!h) {
        const size_t capacity = capacity_for(bytes);
        if (capacity > std::numeric_limits<size_t>::max() - sizeof(Header)) return nullptr;
        h = static_cast<Header*>(std::malloc(sizeof(Header) + capacity));
        if (!h) return nullptr;
        h->capacity = capacity;
    }
    h->size = bytes;
    return h + 1;
}

void* kept_calloc(size_t count, size_t size) {
    if (size != 0 && count > std::numeric_limits<size_t>::max() / size) return nullptr;
    void* p = kept_malloc(count * size);
    if (p) std::memset(p, 0, count * size);
    return p;
}

void* kept_realloc(void* p, size_t bytes) {
    if (!p) return kept_malloc(bytes);
    Header* h = header_of(p);
    bytes = std::max<size_t>(bytes, 1);
    if (bytes <= h->capacity) {
        h->size = bytes;
        return p;
    }
    void* q = kept_malloc(bytes);
    if (!q) return nullptr;  // realloc's contract: the old block stays as it was
    std::memcpy(q, p, h->size);
    kept_free(p);
    return q;
}

void kept_free(void* p) {
    if (!p) return;
    Header* h = header_of(p);
    if (h->capacity >= kKeptMin) {
        std::lock_guard<std::mutex> lock(kept_lock());
        if (kept_total + h->capacity <= kKeptMax) {
            kept_blocks().emplace_back(h->capacity, h);
            kept_total += h->capacity;
            return;
        }
    }
    std::free(h);
}

void keep_touched_blocks(const std::vector<size_t>& sizes) {
    std::vector<void*> held;
    size_t total = cholmod_kept_bytes();
    for (size_t bytes : sizes) {
        const size_t capacity = capacity_for(bytes);
        if (bytes < kKeptMin || total + capacity > kKeptMax) continue;  // past the cap it would be freed again
        total += capacity;
        void* p = kept_malloc(bytes);
        if (!p) break;
        std::memset(p, 0, bytes);
        held.push_back(p);
    }
    for (void* p : held) kept_free(p);
}

size_t cholmod_kept_bytes() {
    std::lock_guard<std::mutex> lock(kept_lock());
    return kept_total;
}

void release_kept_pages() {
    std::lock_guard<std::mutex> lock(kept_lock());
    for (const auto& [capacity, h] : kept_blocks()) std::free(h);
    kept_blocks().clear();
    kept_total = 0;
}

void keep_cholmod_pages() {
    static std::once_flag once;
    std::call_once(once, [] {
        SuiteSparse_config.malloc_func = kept_malloc;
        SuiteSparse_config.calloc_func = kept_calloc;
        SuiteSparse_config.realloc_func = kept_realloc;
        SuiteSparse_config.free_func = kept_free;
    });
}

}  // namespace xcut
