#pragma once
// The studies' plots are drawn by the Python scripts of tools/report/, run as a child process.
#include <string>

namespace xcut {

/// Runs the plot script `script` from tools/report/ with the system's python3 and `arguments`
/// (already quoted). It is looked for beside the executable (<bin>/../tools/report in a build tree,
/// <prefix>/share/xcut/report once installed), then under the working directory. Plots are
/// optional: when the script, python3 or matplotlib is missing it prints a warning and returns false.
bool run_plot_script(const std::string& script, const std::string& arguments);

/// The path of tools/<folder>/<script> beside the executable (build tree), under
/// <prefix>/share/xcut/<folder> (installed), or under the working directory; empty if none.
std::string find_script(const std::string& folder, const std::string& script);
/// Debian's /usr/bin/python3 when present (its packages: matplotlib), else python3 from PATH.
std::string system_python();

}  // namespace xcut
