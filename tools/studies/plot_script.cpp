#include "tools/studies/plot_script.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

namespace xcut {

std::string find_script(const std::string& folder, const std::string& script) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path bin = fs::read_symlink("/proc/self/exe", ec).parent_path();
    for (const fs::path& p : {bin / ".." / "tools" / folder / script, bin / ".." / "share" / "xcut" / folder / script,
                              fs::path("tools") / folder / script})
        if (fs::exists(p, ec)) return p.lexically_normal().string();
    return "";
}

std::string system_python() {
    // Debian's python3-matplotlib is installed for the system interpreter; a python3 earlier on
    // PATH (a virtual environment) may not have it.
    return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

bool run_plot_script(const std::string& script, const std::string& arguments) {
    const std::string path = find_script("report", script);
    const int rc = path.empty() ? -1 : std::system(fmt::format("{} '{}' {}", system_python(), path, arguments).c_str());
    if (rc != 0)
        fmt::print(stderr, "warning: no plots ({}); the CSVs are complete\n",
                   path.empty() ? "tools/report/" + script + " not found" : "python3 with matplotlib failed");
    return rc == 0;
}

}  // namespace xcut
