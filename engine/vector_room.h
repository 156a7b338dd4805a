#pragma once
// Vectors that grow with room. A cut grows the step's arrays by a few entries; storage grown to the
// exact size is copied to fresh pages at every split, and first touches of fresh pages cost a virtual
// machine like this one about 7 us a 4 KiB page (a 1 MB copy 2.8 ms, docs/BENCHMARKS.md, Real time
// through a cut). Storage grown by half again is reused by the next few splits.
#include <cstddef>
#include <vector>

namespace xcut {

/// Resizes v to n, growing its storage by half again when it must grow.
template <class T>
void resize_with_room(std::vector<T>& v, size_t n) {
    if (n > v.capacity()) v.reserve(n + n / 2);
    v.resize(n);
}

/// v = from, in v's storage when it holds from, else in storage grown by half again.
template <class T>
void assign_with_room(std::vector<T>& v, const std::vector<T>& from) {
    if (from.size() > v.capacity()) v.clear(), v.reserve(from.size() + from.size() / 2);
    v.assign(from.begin(), from.end());
}

}  // namespace xcut
