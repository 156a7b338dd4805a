#pragma once
// The dense kernels of a supernodal triangular solve (systems/solver/lower_factor.h): one supernode's
// columns of L x = b and of L^T x = b, on its rows x cols column-major block [L11; L21] (L11 lower
// triangular, its diagonal the pivots). Column-oriented forward elimination and row-oriented
// (dot-product) back substitution, as in any supernodal solve (Ng & Peyton 1993, "Block sparse
// Cholesky algorithms on advanced uniprocessor computers"; CHOLMOD's cholmod_super_lsolve and
// cholmod_super_ltsolve do the same with BLAS trsv and gemv).
//
// The step's CG applies the factor once an iteration, and on large factors these kernels are a large
// part of the step (the 1 mm skin: a third of its samples under perf record with Eigen's kernels,
// docs/BENCHMARKS.md). They are compiled twice: for any
// x86-64 (SSE2: the portable build) and for AVX2, taken at run time where the CPU has it (as
// OpenBLAS picks its kernels by CPU). Both give the same bits: every sum is taken in an order the
// source fixes, not the vector width: a forward update runs each row's columns in increasing
// order (element-wise, whatever the width), and each dot product of the back substitution keeps
// eight partial sums, lane l taking rows l, l + 8, ... from the first row below the column's block
// of four, combined as ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7)), the rows past the last
// whole eight added after in order, then the block's own rows. No fused multiply-add (the file is built
// with -ffp-contract=off, and the AVX2 version does not enable FMA), which would round differently.
// A result therefore does not depend on the machine's vector unit, and a run on a machine without
// AVX2 has the bits of one with it.
//
// XCUT_KERNELS in the environment: "auto" (or unset) as above, "generic" the portable kernels on any
// CPU (to compare), "avx2" the AVX2 ones (an error where the CPU lacks AVX2).

namespace xcut {

template <class Real>
struct SupernodeKernels {
    /// L w = b on the supernode's rows (L = [L11; L21], rows x cols, column-major): w[0, cols) holds
    /// b's part on its columns and becomes x_s = L11^-1 b_s; w[cols, rows) holds zeros and becomes
    /// -L21 x_s, the updates to add to the rows below.
    void (*forward)(const Real* L, int rows, int cols, Real* w);
    /// L^T w = b on the supernode's rows: w[cols, rows) holds the solution on the rows below; w[0,
    /// cols) holds b's part on its columns and becomes x_s = L11^-T (b_s - L21^T w_below).
    void (*backward)(const Real* L, int rows, int cols, Real* w);
    const char* name;  ///< "generic" or "avx2"
};

/// The kernels the solves use, taken once: AVX2 where the CPU has it, unless XCUT_KERNELS=generic;
/// the portable ones otherwise. Throws std::invalid_argument for another value of XCUT_KERNELS, or
/// "avx2" on a CPU without it.
template <class Real>
const SupernodeKernels<Real>& supernode_kernels();
/// The kernels for a value of XCUT_KERNELS (null: unset), as supernode_kernels() takes them once.
template <class Real>
const SupernodeKernels<Real>& supernode_kernels_for(const char* setting);
/// The portable kernels, and the AVX2 ones (null where the CPU lacks AVX2): for the tests that
/// compare them.
template <class Real>
const SupernodeKernels<Real>& supernode_kernels_generic();
template <class Real>
const SupernodeKernels<Real>* supernode_kernels_avx2();

}  // namespace xcut
