#include "tools/studies/plot_script.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

namespace xcut {

bool run_plot_script(const std::string& script, const std::string& arguments) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    std::string path;
    const fs::path bin = exe.parent_path();
    for (const fs::path& p : {bin / ".." / "tools" / "report" / script, bin / ".." / "share" / "xcut" / "report" / script,
                              fs::path("tools") / "report" / script})
        if (path.empty() && fs::exists(p, ec)) path = p.lexically_normal().string();
    // Debian's python3-matplotlib is installed for the system interpreter; a python3 earlier on
    // PATH (a virtual environment) may not have it.
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const int rc = path.empty() ? -1 : std::system(fmt::format("{} '{}' {}", python, path, arguments).c_str());
    if (rc != 0)
        fmt::print(stderr, "warning: no plots ({}); the CSVs are complete\n",
                   path.empty() ? "tools/report/" + script + " not found" : "python3 with matplotlib failed");
    return rc == 0;
}

}  // namespace xcut
