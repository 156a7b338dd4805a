#pragma once
// What the runtimes read once, when they load (before main), set by the programs that run the
// engine: the xcut program and the test programs. Python's package sets the wait policy itself
// before it loads the engine (tools/python/xcut/__init__.py).

namespace xcut {

/// Sets what the runtimes read at load (unless the user chose) and starts the program again, once
/// (execv of /proc/self/exe with `argv`; on failure it runs on as started):
///  - Waiting OpenMP threads spin a core by default (libgomp: about 300,000 spins before they
///    sleep). Beside a renderer, a haptic thread or another process, that core is taken from them,
///    and every parallel region then waits for a descheduled thread: 2 threads ran 6-16x slower
///    than 1 under load; two quadratic stress tests side by side took 55 s, 30 s passive. So
///    OMP_WAIT_POLICY=passive.
///  - The first touch of a fresh 4 KiB page costs a virtual machine of this project's kind a
///    trap to the hypervisor; a multigrid setup at 53k tets spent most of its time there
///    (770-910 ms against 180-270 ms with huge pages, docs/BENCHMARKS.md). Where the kernel gives
///    transparent huge pages on request, glibc.malloc.hugetlb=1 makes malloc ask (2 MiB at a
///    time; peak memory about 6 % higher at 53k tets). GLIBC_TUNABLES with a hugetlb setting of
///    the user's own (glibc.malloc.hugetlb=0: off) is left as it is.
void ensure_startup_environment(char** argv);

}  // namespace xcut
