#include "engine/startup_environment.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace xcut {
namespace {

/// Whether the kernel gives transparent huge pages only to memory that asks for them
/// (/sys/kernel/mm/transparent_hugepage/enabled reads "always madvise never" with [madvise]).
bool huge_pages_on_request() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(in, mode);
    return mode.find("[madvise]") != std::string::npos;
}

}  // namespace

void ensure_startup_environment(char** argv) {
    bool changed = false;
    if (std::getenv("OMP_WAIT_POLICY") == nullptr) setenv("OMP_WAIT_POLICY", "passive", 1), changed = true;
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    const std::string current = tunables ? tunables : "";
    if (current.find("glibc.malloc.hugetlb") == std::string::npos && huge_pages_on_request()) {
        const std::string with_huge = (current.empty() ? current : current + ":") + "glibc.malloc.hugetlb=1";
        setenv("GLIBC_TUNABLES", with_huge.c_str(), 1);
        changed = true;
    }
    if (changed) execv("/proc/self/exe", argv);  // returns only on failure: run on as started
}

}  // namespace xcut
