// CHOLMOD's memory kept for the next factor (systems/solver/cholmod_pages.h): a large freed block
// comes back for a request that fits, a small one goes to the C library, realloc keeps the
// contents, calloc zeroes, and a factor computed again reuses the pages of the one before.
#include <gtest/gtest.h>

#include <SuiteSparse_config.h>

#include <cstring>

#include "engine/background_threads.h"
#include "systems/solver/cholesky_factor.h"
#include "systems/solver/factor_background.h"
#include "systems/solver/cholmod_pages.h"

namespace xcut {
namespace {

constexpr size_t kLarge = size_t{1} << 20;  // 1 MiB: kept when freed

/// The entries of a 1D Laplacian of n rows, shifted to be positive definite.
std::vector<Eigen::Triplet<double>> laplacian_1d(int n) {
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < n; ++i) {
        entries.emplace_back(i, i, 2.5);
        if (i + 1 < n) entries.emplace_back(i + 1, i, -1.0), entries.emplace_back(i, i + 1, -1.0);
    }
    return entries;
}

TEST(CholmodPages, SuiteSparseAllocatesThroughThem) {
    EXPECT_EQ(SuiteSparse_config.malloc_func, &kept_malloc);
    EXPECT_EQ(SuiteSparse_config.calloc_func, &kept_calloc);
    EXPECT_EQ(SuiteSparse_config.realloc_func, &kept_realloc);
    EXPECT_EQ(SuiteSparse_config.free_func, &kept_free);
}

TEST(CholmodPages, ALargeFreedBlockComesBackForARequestThatFits) {
    release_kept_pages();
    void* a = kept_malloc(kLarge);
    ASSERT_NE(a, nullptr);
    const size_t before = cholmod_kept_bytes();
    kept_free(a);
    EXPECT_GE(cholmod_kept_bytes(), before + kLarge);
    void* b = kept_malloc(kLarge + kLarge / 16);  // a little larger: within the room it was given
    EXPECT_EQ(b, a);
    EXPECT_EQ(cholmod_kept_bytes(), before);
    void* c = kept_malloc(kLarge / 4);  // far smaller: not handed a block four times its size
    EXPECT_NE(c, a);
    kept_free(c);
    kept_free(b);
}

TEST(CholmodPages, ASmallBlockIsNotKept) {
    const size_t before = cholmod_kept_bytes();
    kept_free(kept_malloc(1000));
    EXPECT_EQ(cholmod_kept_bytes(), before);
}

TEST(CholmodPages, ReallocKeepsTheContentsAndCallocZeroes) {
    auto* p = static_cast<unsigned char*>(kept_malloc(300));
    for (int i = 0; i < 300; ++i) p[i] = static_cast<unsigned char>(i);
    p = static_cast<unsigned char*>(kept_realloc(p, 2 * kLarge));
    ASSERT_NE(p, nullptr);
    for (int i = 0; i < 300; ++i) ASSERT_EQ(p[i], static_cast<unsigned char>(i));
    p = static_cast<unsigned char*>(kept_realloc(p, 100));  // shrinks in place
    for (int i = 0; i < 100; ++i) ASSERT_EQ(p[i], static_cast<unsigned char>(i));
    kept_free(p);
    auto* z = static_cast<unsigned char*>(kept_calloc(3, kLarge));  // may be a kept, used block
    ASSERT_NE(z, nullptr);
    for (size_t i = 0; i < 3 * kLarge; i += 4093) ASSERT_EQ(z[i], 0);
    kept_free(z);
    EXPECT_EQ(kept_calloc(SIZE_MAX / 2, 4), nullptr);  // the product overflows
}

TEST(CholmodPages, AFactorComputedAgainReusesThePagesOfTheOneBefore) {
    // A 1D Laplacian of 30,000 rows: its factor's arrays (about 11 MB in all) are well over the
    // kept size, and two factors' worth stay under the cap.
    const int n = 30000;
    const std::vector<Eigen::Triplet<double>> entries = laplacian_1d(n);
    auto factor_once = [&] {
        LinearFactor f;
        f.matrix.resize(n, n);
        f.matrix.setFromTriplets(entries.begin(), entries.end());
        EXPECT_TRUE(compute_factor(f, true));
    };
    release_kept_pages();
    factor_once();
    const size_t kept = cholmod_kept_bytes();
    EXPECT_GT(kept, size_t{256} << 10);  // the first factor's large blocks, freed with it
    factor_once();
    // The second took them again and gave them back; without reuse it would have added its own.
    EXPECT_GE(cholmod_kept_bytes(), kept);
    EXPECT_LT(cholmod_kept_bytes(), kept + kept / 2);
    release_kept_pages();
    EXPECT_EQ(cholmod_kept_bytes(), 0u);
}

// A factor solved in single precision keeps its rounded copy in the kept blocks too: freed with
// the factor, it is there for the next one's, which takes it again.
TEST(CholmodPages, ASinglePrecisionCopyIsKeptForTheNextFactor) {
    const int n = 30000;
    const std::vector<Eigen::Triplet<double>> entries = laplacian_1d(n);
    size_t single_bytes = 0;
    auto factor_once = [&] {
        LinearFactor f(true);
        f.single_from = 0.0;
        f.matrix.resize(n, n);
        f.matrix.setFromTriplets(entries.begin(), entries.end());
        ASSERT_TRUE(compute_factor(f, true));
        ASSERT_TRUE(f.lower && f.lower->is_single());
        single_bytes = f.lower->single.size() * sizeof(float);
    };
    release_kept_pages();
    factor_once();
    ASSERT_GE(single_bytes, size_t{256} << 10) << "large enough to be kept";
    const size_t kept = cholmod_kept_bytes();
    release_kept_pages();
    {
        LinearFactor in_double(true);  // the same factor in double: what CHOLMOD's blocks alone keep
        in_double.matrix.resize(n, n);
        in_double.matrix.setFromTriplets(entries.begin(), entries.end());
        ASSERT_TRUE(compute_factor(in_double, true));
        ASSERT_FALSE(in_double.lower->is_single());
    }
    EXPECT_GE(kept, cholmod_kept_bytes() + single_bytes) << "the single copy went to the kept blocks";
    release_kept_pages();
    factor_once();
    const size_t again = cholmod_kept_bytes();
    factor_once();
    EXPECT_LT(cholmod_kept_bytes(), again + single_bytes) << "the second factor took the copy's block again";
    release_kept_pages();
}

TEST(CholmodPages, TouchedBlocksAreHeldForTheNextRequests) {
    release_kept_pages();
    keep_touched_blocks({kLarge, 2 * kLarge, 100});  // the small one is not kept
    const size_t held = cholmod_kept_bytes();
    EXPECT_GE(held, 3 * kLarge);
    EXPECT_LT(held, 4 * kLarge);
    void* p = kept_malloc(2 * kLarge);  // one of them comes back
    EXPECT_LT(cholmod_kept_bytes(), held - kLarge);
    kept_free(p);
    release_kept_pages();
}

// The factor made at load warms blocks the size of its largest arrays for its first successor, on
// the background thread (systems/solver/factor_background.h).
TEST(CholmodPages, AFactorWarmsBlocksOfItsArraysSizesForItsSuccessor) {
    const int n = 30000;
    const std::vector<Eigen::Triplet<double>> entries = laplacian_1d(n);
    LinearFactor f(true);
    f.single_from = 0.0;
    f.matrix.resize(n, n);
    f.matrix.setFromTriplets(entries.begin(), entries.end());
    ASSERT_TRUE(compute_factor(f, true));
    const cholmod_factor* L = f.llt.factor();
    ASSERT_TRUE(L && L->is_super && f.lower->is_single());
    release_kept_pages();
    warm_pages_for_successor(f);
    run_in_background<int>([] { return 0; }).get();  // the jobs run in order: the warming is done
    size_t expected = 0;
    for (size_t bytes : {L->xsize * sizeof(double), L->ssize * sizeof(int), f.lower->single.size() * sizeof(float)})
        if (bytes >= (size_t{256} << 10)) expected += bytes;
    EXPECT_GT(expected, 0u);
    EXPECT_GE(cholmod_kept_bytes(), expected);
    release_kept_pages();
}

}  // namespace
}  // namespace xcut
