// The installed package: `cmake --install` of this build tree into a temporary prefix, then
// docs/example configured with find_package(xcut CONFIG REQUIRED), built, and run on the cantilever
// scene; it must print a finite, positive displacement. Takes a minute or two (one compile). The
// installed library holds the engine, the systems and the components and no benchmark or study, and
// the package carries the scenes and the report scripts the binary calls.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// Runs a shell command with its output in `log`; true on exit status 0.
bool run(const std::string& command, const fs::path& log) {
    const std::string full = command + " > " + quote(log.string()) + " 2>&1";
    const int status = std::system(full.c_str());
    if (status != 0) ADD_FAILURE() << full << "\nexit status " << status << "\n" << slurp(log);
    return status == 0;
}

TEST(InstallPackage, ExampleBuildsAndRunsAgainstTheInstalledLibrary) {
    const fs::path dir = fs::temp_directory_path() / ("xcut_install_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path prefix = dir / "prefix", build = dir / "example", log = dir / "log.txt";
    const std::string cmake = quote(XCUT_CMAKE_COMMAND);

    ASSERT_TRUE(run(cmake + " --install " + quote(XCUT_BUILD_DIR) + " --prefix " + quote(prefix.string()), log));
    EXPECT_TRUE(fs::exists(prefix / "include/xcut/engine/simulation.h"));
    EXPECT_TRUE(fs::exists(prefix / "include/xcut/components/nodes.h"));
    EXPECT_TRUE(fs::exists(prefix / "include/xcut/systems/solver/solver_system.h"));
    ASSERT_TRUE(fs::exists(prefix / "lib/cmake/xcut/xcutConfig.cmake"));
    EXPECT_TRUE(fs::exists(prefix / "share/xcut/scenes/skin_slab.json"));
    EXPECT_TRUE(fs::exists(prefix / "share/xcut/scenes/meshes/abdominal_wall.msh")) << "the mesh files scenes read";
    EXPECT_TRUE(fs::exists(prefix / "share/xcut/report/plot_compare.py"));
    EXPECT_FALSE(fs::exists(prefix / "include/xcut/tools")) << "the studies are not the engine";

    // No benchmark or study symbol in libxcut_core.a: those live in tools/ (library xcut_studies).
    const fs::path symbols = dir / "symbols.txt";
    ASSERT_TRUE(run("nm -C --defined-only " + quote((prefix / "lib/libxcut_core.a").string()), symbols));
    std::ifstream nm(symbols);
    int ours = 0;
    for (std::string line; std::getline(nm, line);) {
        const size_t at = line.find(" xcut::");
        if (at == std::string::npos) continue;
        ++ours;
        const std::string name = line.substr(at + 1, line.find('(', at) - at - 1);
        EXPECT_FALSE(std::regex_search(name, std::regex("bench|stress_|Stress[A-Z]|compare_|Compare[A-Z]|accuracy|roofline|crack_reference|kernel_model",
                                                        std::regex::icase)))
            << line;
    }
    EXPECT_GT(ours, 100) << "the core library's own symbols were not read";

    // Same compiler as this build; an ASan build's library needs the sanitizer flags in its users too.
    ASSERT_TRUE(run(cmake + " -S " + quote(std::string(XCUT_SOURCE_DIR) + "/docs/example") + " -B " +
                        quote(build.string()) + " -G " + quote(XCUT_CMAKE_GENERATOR) + " -DCMAKE_BUILD_TYPE=Release" +
                        " -DCMAKE_CXX_COMPILER=" + quote(XCUT_CXX_COMPILER) + " -DCMAKE_PREFIX_PATH=" +
                        quote(prefix.string()) + " -DCMAKE_CXX_FLAGS=" + quote(XCUT_EXAMPLE_CXX_FLAGS),
                    log));
    ASSERT_TRUE(run(cmake + " --build " + quote(build.string()), log));

    const fs::path out = dir / "out.txt";
    ASSERT_TRUE(run(quote((build / "xcut_example").string()) + " " +
                        quote(std::string(XCUT_SOURCE_DIR) + "/scenes/cantilever.json") + " 5",
                    out));
    const std::string text = slurp(out);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(text, m, std::regex("max displacement ([^ ]+) m"))) << text;
    const double d = std::strtod(m[1].str().c_str(), nullptr);
    EXPECT_TRUE(std::isfinite(d)) << text;
    EXPECT_GT(d, 0.0) << text;
    EXPECT_LT(d, 0.01) << "a 0.1 m beam sagging under its own weight: " << text;

    // The installed binary runs an installed scene that reads an installed mesh file.
    const fs::path schedule = dir / "schedule.txt";
    EXPECT_TRUE(run(quote((prefix / "bin/xcut").string()) + " schedule " +
                        quote((prefix / "share/xcut/scenes/layered_incision.json").string()),
                    schedule))
        << slurp(schedule);
    fs::remove_all(dir);
}

}  // namespace
