#pragma once
// CHOLMOD's memory, kept for the next factor. A factor renewed off the step
// (systems/solver/factor_background.h) allocates its L and CHOLMOD's work arrays anew each time, and
// the first touch of fresh pages costs a virtual machine of this project's kind as much again as
// the factorization itself: 18-20 ms against 8 ms for the same numeric factorization of the default
// skin when the pages come back from an earlier factor (docs/BENCHMARKS.md, cutstep). SuiteSparse
// lets a program give its own allocation functions (SuiteSparse_config, SuiteSparse 5); these keep
// the blocks of 256 KiB and more that CHOLMOD frees (a retired factor's, a factorization's work
// arrays), up to 128 MiB in all, and hand them back for a request that fits, so their pages are
// touched once per process, not once per factor. Smaller blocks, and blocks past the cap, go to
// the C library as before. A factor's own large arrays beside CHOLMOD's (its single-precision
// copy, KeptArray) are kept the same way.
#include <cstddef>
#include <new>
#include <vector>

namespace xcut {

/// Routes SuiteSparse's allocations through the kept blocks; once per process, before CHOLMOD's
/// first allocation (systems/solver/cholesky_factor.cpp calls it during static initialization).
void keep_cholmod_pages();

/// Bytes of freed blocks held for reuse now.
size_t cholmod_kept_bytes();

/// Gives every held block back to the C library (a program done with its factors; tests).
void release_kept_pages();

/// Blocks of these sizes (those of at least the kept size, while they fit within the cap), each
/// written once and held for reuse: a factor's first successor then finds pages already touched, as later
/// ones find their predecessor's. Run on the background thread (warm_pages_for_successor,
/// systems/solver/factor_background.h).
void keep_touched_blocks(const std::vector<size_t>& sizes);

/// The same functions SuiteSparse is given, for tests: malloc, calloc, realloc and free.
void* kept_malloc(size_t bytes);
void* kept_calloc(size_t count, size_t size);
void* kept_realloc(void* p, size_t bytes);
void kept_free(void* p);

/// An array of n trivially copyable T in the kept blocks, its entries left uninitialized.
template <class T>
class KeptArray {
public:
    KeptArray() = default;
    KeptArray(const KeptArray&) = delete;
    KeptArray& operator=(const KeptArray&) = delete;
    ~KeptArray() { kept_free(data_); }
    /// n entries (their values undefined); throws std::bad_alloc if they cannot be had.
    void resize(size_t n) {
        kept_free(data_);
        data_ = nullptr, size_ = 0;
        if (n == 0) return;
        data_ = static_cast<T*>(kept_malloc(n * sizeof(T)));
        if (!data_) throw std::bad_alloc();
        size_ = n;
    }
    T* data() { return data_; }
    const T* data() const { return data_; }
    size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    T& operator[](size_t i) { return data_[i]; }

private:
    T* data_ = nullptr;
    size_t size_ = 0;
};

}  // namespace xcut
