#include "tools/studies/calculix_reference.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/fnv_hash.h"
#include "tools/studies/plot_script.h"

namespace xcut {

namespace {

namespace fs = std::filesystem;

bool on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "");
    std::error_code ec;
    for (std::string d; std::getline(dirs, d, ':');)
        if (!d.empty() && fs::exists(fs::path(d) / program, ec)) return true;
    return false;
}

ExternalReference read_result(const std::string& path) {
    std::ifstream in(path);
    ExternalReference r;
    r.path = path;
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        r.solver = j.at("solver").get<std::string>();
        r.values = j.at("values").get<std::vector<double>>();
        r.error_estimate = j.at("error_estimate").get<double>();
        r.order = j.at("observed_order").get<double>();
        for (const auto& level : j.at("levels")) {
            r.levels.push_back(level.at("n").get<int>());
            r.dofs.push_back(level.at("dofs").get<int>());
            r.seconds.push_back(level.at("seconds").get<double>());
            r.level_value.push_back(level.at("values").at(0).get<double>());
        }
        r.available = !r.values.empty();
    } catch (const nlohmann::json::exception& e) {
        r.why = fmt::format("{}: not a reference the script wrote ({})", path, e.what());
    }
    return r;
}

}  // namespace

ExternalReference calculix_reference(int problem, const nlohmann::json& params, const std::vector<int>& levels,
                                     const std::string& cache_dir) {
    ExternalReference r;
    const std::string script = find_script("reference", "calculix_reference.py");
    if (script.empty()) return r.why = "tools/reference/calculix_reference.py not found", r;
    if (!on_path("ccx")) return r.why = "CalculiX (ccx, Debian's calculix-ccx) is not installed", r;
    std::ifstream source(script);
    std::stringstream code;
    code << source.rdbuf();
    const uint64_t inputs = fnv1a(fmt::format("{}|{}|{}", problem, params.dump(), fmt::join(levels, ",")));
    const std::string key = fmt::format("{:016x}", fnv1a(code.str(), inputs));
    std::error_code ec;
    fs::create_directories(cache_dir, ec);
    const std::string out = (fs::path(cache_dir) / fmt::format("calculix_p{}_{}.json", problem, key)).string();
    if (fs::exists(out, ec)) {
        ExternalReference cached = read_result(out);
        cached.from_cache = cached.available;
        if (cached.available) return cached;
    }
    const std::string in = (fs::path(cache_dir) / fmt::format("calculix_p{}_{}_params.json", problem, key)).string();
    std::ofstream(in) << params.dump(1);
    const std::string cmd = fmt::format("{} '{}' {} '{}' {} '{}'", system_python(), script, problem, in,
                                        fmt::join(levels, ","), out);
    if (std::system(cmd.c_str()) != 0) return r.why = fmt::format("CalculiX's reference failed: {}", cmd), r;
    return read_result(out);
}

}  // namespace xcut
