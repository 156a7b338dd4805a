// The command line (tools/xcut.cpp and its subcommands): errors become exit code 2 with the file and
// field named, --help exits 0, and a run writes its series and metrics.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/test_helpers.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

using testing::temp_dir;

const char* kTiny = R"({
  "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [2, 2, 2] },
  "constraints": { "fixed_boxes": [ { "min": [-1, -1, -1], "max": [1, 1, 1e-9] } ] },
  "steps": 3
})";

/// Runs the xcut binary; returns its exit code and its stderr.
int run_xcut(const std::string& args, std::string& err) {
    const fs::path log = fs::temp_directory_path() / ("xcut_cli_" + std::to_string(::getpid()) + ".err");
    const std::string cmd = std::string(XCUT_BINARY) + " " + args + " > /dev/null 2> " + log.string();
    const int status = std::system(cmd.c_str());
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    err = ss.str();
    fs::remove(log);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Cli, BadSceneExitsWithTwoAndNamesTheField) {
    const fs::path dir = temp_dir("cli_bad");
    std::ofstream(dir / "bad.json") << R"({ "mesh": { "generator": "box", "size": [1, 1, 1], "cells": [1, 1, 1] }, "solver": { "dt": -1 } })";
    std::string err;
    EXPECT_EQ(run_xcut("run " + (dir / "bad.json").string(), err), 2);
    EXPECT_NE(err.find("bad.json: solver.dt"), std::string::npos) << err;
    fs::remove_all(dir);
}

// A run that cannot go on stops with exit code 3 and says why: infinite forces (g = 1e300), a solve
// that cannot converge (one CG iteration); it never aborts in a library nor exits 0 with garbage.
TEST(Cli, NumericalFailureExitsWithThreeAndSaysWhy) {
    const fs::path dir = temp_dir("cli_numerical");
    std::ofstream(dir / "tiny.json") << kTiny;
    const std::string scene = (dir / "tiny.json").string() + " -q -o " + (dir / "out").string();
    std::string err;
    EXPECT_EQ(run_xcut("run " + scene + " --set gravity=[0,0,-1e300]", err), 3) << err;
    EXPECT_NE(err.find("NaN or infinite"), std::string::npos) << err;
    EXPECT_EQ(run_xcut("run " + scene + " --set solver.cg_max_iterations=1 --set solver.linear=\\\"jacobi\\\" "
                       "--set gravity=[0,0,-9.81]", err), 3) << err;
    EXPECT_NE(err.find("relative residual"), std::string::npos) << err;
    fs::remove_all(dir);
}

// Waiting threads do not spin a core away from other work: xcut sets OpenMP's passive wait policy
// itself (it restarts once with it), and keeps one the user chose.
TEST(Cli, OpenMpThreadsWaitPassively) {
    const fs::path dir = temp_dir("cli_wait");
    std::ofstream(dir / "tiny.json") << kTiny;
    const fs::path out = dir / "stdout.txt";
    const std::string run = std::string(XCUT_BINARY) + " run " + (dir / "tiny.json").string() + " -q --steps 1 -o " +
                            (dir / "out").string() + " > " + out.string() + " 2>&1";
    ASSERT_EQ(std::system(("env -u OMP_WAIT_POLICY " + run).c_str()), 0);
    std::stringstream text;
    text << std::ifstream(out).rdbuf();
    EXPECT_NE(text.str().find("OpenMP wait passive"), std::string::npos) << text.str();
    ASSERT_EQ(std::system(("OMP_WAIT_POLICY=active " + run).c_str()), 0);
    std::stringstream chosen;
    chosen << std::ifstream(out).rdbuf();
    EXPECT_NE(chosen.str().find("OpenMP wait active"), std::string::npos) << chosen.str();
    fs::remove_all(dir);
}

// Malloc asks for transparent huge pages where the kernel gives them on request (xcut sets
// glibc.malloc.hugetlb=1 and restarts once), and a setting of the user's own is kept.
TEST(Cli, MallocAsksForHugePagesWhereTheKernelGivesThemOnRequest) {
    std::string mode;
    std::getline(std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled"), mode);
    const bool on_request = mode.find("[madvise]") != std::string::npos;
    const fs::path dir = temp_dir("cli_huge");
    std::ofstream(dir / "tiny.json") << kTiny;
    const fs::path out = dir / "stdout.txt";
    const std::string run = std::string(XCUT_BINARY) + " run " + (dir / "tiny.json").string() + " -q --steps 1 -o " +
                            (dir / "out").string() + " > " + out.string() + " 2>&1";
    const auto said = [&] {
        std::stringstream text;
        text << std::ifstream(out).rdbuf();
        return text.str();
    };
    ASSERT_EQ(std::system(("env -u GLIBC_TUNABLES " + run).c_str()), 0);
    EXPECT_NE(said().find(on_request ? "malloc huge pages on" : "malloc huge pages off"), std::string::npos) << said();
    ASSERT_EQ(std::system(("GLIBC_TUNABLES=glibc.malloc.hugetlb=0 " + run).c_str()), 0);
    EXPECT_NE(said().find("malloc huge pages off"), std::string::npos) << said();
    fs::remove_all(dir);
}

TEST(Cli, HelpExitsWithZero) {
    std::string err;
    EXPECT_EQ(run_xcut("run --help", err), 0);
    EXPECT_EQ(run_xcut("--help", err), 0);
}

TEST(Cli, RunWritesSeriesAndMetrics) {
    const fs::path dir = temp_dir("cli_run");
    std::ofstream(dir / "tiny.json") << kTiny;
    std::string err;
    ASSERT_EQ(run_xcut("run " + (dir / "tiny.json").string() + " -q --steps 3 --set output.every=1 -o " + (dir / "out").string(), err), 0) << err;
    EXPECT_TRUE(fs::exists(dir / "out" / "tiny.pvd"));
    for (int s = 0; s <= 3; ++s) EXPECT_TRUE(fs::exists(dir / "out" / ("tiny_00000" + std::to_string(s) + ".vtu")));
    std::ifstream csv(dir / "out" / "tiny_metrics.csv");
    std::string header, row;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("step,time_s,dt_s,dofs,cg_iterations,cg_residual,kinetic_J,elastic_J,gravity_work_J,step_ms", 0), 0u)
        << header;
    int rows = 0;
    while (std::getline(csv, row)) {
        ++rows;
        std::stringstream ss(row);
        std::string cell;
        while (std::getline(ss, cell, ',')) EXPECT_TRUE(std::isfinite(std::stod(cell))) << row;
    }
    EXPECT_EQ(rows, 3);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace xcut
