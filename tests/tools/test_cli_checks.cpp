// What `xcut run` says about a scene that is valid but almost surely not meant (plausibility
// warnings at load, with the number and how to silence it), what it flags at the end of a run, the
// bound on what a run writes, a replay that runs to the end of its recording, and the CSV's
// elements_split column against the run's total; benchmarks that refuse options they would ignore
// and never write the record on a partial run.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/test_helpers.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

const char* kCube = R"({
  "mesh": { "generator": "box", "size": [0.01, 0.01, 0.01], "cells": [2, 2, 2] },
  "constraints": { "fixed_boxes": [ { "min": [-1, -1, -1], "max": [1, 1, 1e-9] } ] },
  "steps": 3)";

class CliChecks : public ::testing::Test {
protected:
    void SetUp() override { dir_ = testing::temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name()); }
    void TearDown() override { fs::remove_all(dir_); }
    /// `xcut run` on the cube with `extra` scene fields and `args`; exit code, output in `out`.
    int run(const std::string& extra, const std::string& args, std::string& out) {
        std::ofstream(dir_ / "cube.json") << kCube << extra << "\n}";
        return testing::run_command(std::string(XCUT_BINARY) + " run " + (dir_ / "cube.json").string() + " -q -o " +
                                        (dir_ / "out").string() + " " + args,
                                    out);
    }
    fs::path dir_;
};

TEST_F(CliChecks, ImplausibleMaterialsAreSaidWithTheirNumberAndHowToSilence) {
    std::string out;
    ASSERT_EQ(run(R"(, "material": {"young": 5, "poisson": 0.49, "density": 1e5})", "", out), 0) << out;
    EXPECT_NE(out.find("warning: young: material \"skin\" has E = 5 Pa, outside soft tissue's 100 Pa-100 MPa"),
              std::string::npos) << out;
    EXPECT_NE(out.find("(silence: \"allow\": [\"young\"])"), std::string::npos) << out;
    EXPECT_NE(out.find("warning: density: material \"skin\" has 1e+05 kg/m^3"), std::string::npos) << out;
    EXPECT_NE(out.find("warning: poisson: material \"skin\" has nu = 0.49: linear tetrahedra lock as nu nears 0.5"), std::string::npos) << out;
    ASSERT_EQ(run(R"(, "material": {"young": 5, "poisson": 0.49, "density": 1e5}, "allow": ["young", "density"])",
                  "--allow poisson", out),
              0) << out;
    EXPECT_EQ(out.find("warning: young"), std::string::npos) << out;
    EXPECT_EQ(out.find("warning: density"), std::string::npos) << out;
    EXPECT_EQ(out.find("warning: poisson"), std::string::npos) << out;
    // A plausible scene says nothing of the kind.
    ASSERT_EQ(run("", "--set solver.dt=0.0005", out), 0) << out;
    EXPECT_EQ(out.find("warning:"), std::string::npos) << out;
}

// A mesh file in millimetres read as metres (a 10 cm cube as 100 m), a step larger than the body's
// wave period, a scalpel 10 cm above the body: said at load; at the end, the body that fell out of
// the scene and the blade that cut nothing.
TEST_F(CliChecks, UnitsReachAndTheEndOfTheRun) {
    std::ofstream(dir_ / "tet.vtk") << "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
                                       "0 0 0\n100 0 0\n0 100 0\n0 0 100\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n";
    std::ofstream(dir_ / "mm.json") << R"({"mesh": {"file": "tet.vtk"}, "steps": 2, "allow": ["dt"]})";
    std::string out;
    ASSERT_EQ(testing::run_command(std::string(XCUT_BINARY) + " run " + (dir_ / "mm.json").string() + " -q -o " +
                                       (dir_ / "mm").string(), out), 0) << out;
    EXPECT_NE(out.find("warning: units: body \"body\""), std::string::npos) << out;
    EXPECT_NE(out.find("measures 173 m across"), std::string::npos) << out;
    EXPECT_NE(out.find("needs \"units\": \"mm\""), std::string::npos) << out;

    const std::string scalpel = R"(, "tools": [{"name": "scalpel", "blade": {"tip": [0, 0, -0.002], "heel": [0, 0, 0.002]},
        "trajectory": [{"time": 0, "position": [-0.01, 0.005, 0.1]}, {"time": 1, "position": [0.02, 0.005, 0.1]}]}])";
    ASSERT_EQ(run(scalpel + R"(, "gravity": [0, 0, -9.81], "solver": {"dt": 0.01})", "--set 'constraints={}' --steps 100", out),
              0) << out;
    EXPECT_NE(out.find("warning: tool_reach: tool \"scalpel\" never comes within its blade of any body"), std::string::npos)
        << out;
    EXPECT_NE(out.find("warning: dt: solver.dt 0.01 s is longer than the slowest elastic wave's period"),
              std::string::npos) << out;
    EXPECT_NE(out.find("warning: body \"body\" moved"), std::string::npos) << out;
    EXPECT_NE(out.find("it left the scene"), std::string::npos) << out;
    EXPECT_NE(out.find("warning: tool \"scalpel\" cut nothing"), std::string::npos) << out;
}

TEST_F(CliChecks, OutputVolumeIsBounded) {
    std::string out;
    EXPECT_EQ(run("", "--set steps=100000000 --set output.every=1", out), 2) << out;
    EXPECT_NE(out.find("output.every: 100000000 steps writing a frame every 1 would write about"), std::string::npos) << out;
    EXPECT_NE(out.find("above the limit of 20 GB (output.max_gb)"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir_ / "out" / "cube.pvd")) << "refused before anything was written";
}

// A session recorded past the scene's duration replays to the end of the recording.
TEST_F(CliChecks, ReplayRunsToTheEndOfTheRecording) {
    std::string out;
    ASSERT_EQ(run("", "--steps 7 --record " + (dir_ / "session").string(), out), 0) << out;
    ASSERT_EQ(run("", "--replay " + (dir_ / "session").string(), out), 0) << out;
    EXPECT_NE(out.find("replay: 7 steps, as recorded (the scene says 3)"), std::string::npos) << out;
    std::ifstream csv(dir_ / "out" / "cube_metrics.csv");
    int rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    EXPECT_EQ(rows, 1 + 7);
}

// The CSV's elements_split counts what the cutter applied: its column sums to the run's total.
TEST_F(CliChecks, ElementsSplitColumnSumsToTheTotal) {
    std::string out;
    ASSERT_EQ(testing::run_command(std::string(XCUT_BINARY) + " run " + XCUT_SOURCE_DIR + "/scenes/skin_slab.json -q --steps 500 -o " +
                                       (dir_ / "skin").string(), out), 0) << out;
    const size_t at = out.find("cut: ");
    ASSERT_NE(at, std::string::npos) << out;
    const int total = std::stoi(out.substr(at + 5));
    std::ifstream csv(dir_ / "skin" / "skin_slab_metrics.csv");
    std::string line;
    std::getline(csv, line);
    std::vector<std::string> header;
    std::stringstream hs(line);
    for (std::string c; std::getline(hs, c, ',');) header.push_back(c);
    const size_t col = std::find(header.begin(), header.end(), "elements_split") - header.begin();
    ASSERT_LT(col, header.size());
    int sum = 0;
    while (std::getline(csv, line)) {
        std::stringstream ss(line);
        std::string cell;
        for (size_t c = 0; c <= col; ++c) std::getline(ss, cell, ',');
        sum += std::stoi(cell);
    }
    EXPECT_GT(total, 20);
    EXPECT_EQ(sum, total);
}

// A batch run: --no-output writes nothing but what is asked, --summary the final figures as JSON,
// also for a run that fails (its status and message) or a scene that does not load.
TEST_F(CliChecks, SummaryAndNoOutput) {
    std::string out;
    const fs::path summary = dir_ / "summary.json";
    ASSERT_EQ(run(R"(, "material": {"young": 5}, "gravity": [0, 0, -9.81])", "--no-output --summary " + summary.string(), out),
              0) << out;
    EXPECT_FALSE(fs::exists(dir_ / "out")) << "no output directory";
    nlohmann::json j = nlohmann::json::parse(std::ifstream(summary));
    EXPECT_EQ(j["status"], "ok");
    EXPECT_EQ(j["name"], "cube");
    EXPECT_EQ(j["figures"]["steps"], 3);
    EXPECT_GT(j["figures"]["max_displacement_m"].get<double>(), 0.0);
    EXPECT_EQ(j["figures"]["free_dofs"].get<int>(), 3 * 18) << "27 nodes less the 9 held on z = 0";
    ASSERT_FALSE(j["warnings"].empty());
    EXPECT_NE(j["warnings"][0].get<std::string>().find("young"), std::string::npos);
    // A run that stops (infinite gravity): exit 3 and the status says why.
    EXPECT_EQ(run("", "--no-output --summary " + summary.string() + " --set gravity=[0,0,-1e300]", out), 3) << out;
    j = nlohmann::json::parse(std::ifstream(summary));
    EXPECT_EQ(j["status"], "numerical_error");
    EXPECT_NE(j["message"].get<std::string>().find("NaN or infinite"), std::string::npos) << j.dump();
    // A scene that does not load: exit 2, the field named in the message.
    EXPECT_EQ(run("", "--no-output --summary " + summary.string() + " --set solver.dt=-1", out), 2) << out;
    j = nlohmann::json::parse(std::ifstream(summary));
    EXPECT_EQ(j["status"], "input_error");
    EXPECT_NE(j["message"].get<std::string>().find("solver.dt"), std::string::npos) << j.dump();
}

// A benchmark refuses an option its suite does not read, and a partial run writes its quick CSV,
// never the committed record (the default paths are relative to where it runs).
TEST_F(CliChecks, PartialBenchmarksNeverWriteTheRecord) {
    std::string out;
    const std::string bench = "cd " + dir_.string() + " && " + XCUT_BINARY + " bench ";
    EXPECT_EQ(testing::run_command(bench + "--suite mapping --sizes 100", out), 2) << out;
    EXPECT_NE(out.find("the mapping suite does not read it (it reads: --threads, --steps)"), std::string::npos) << out;
    EXPECT_EQ(testing::run_command(bench + "--suite collision --threads 1", out), 2) << out;
    ASSERT_EQ(testing::run_command(bench + "--suite mapping --steps 1 --threads 1", out), 0) << out;
    EXPECT_NE(out.find("a quick or partial run: it writes results/bench_mapping_quick.csv"), std::string::npos) << out;
    EXPECT_TRUE(fs::exists(dir_ / "results" / "bench_mapping_quick.csv"));
    EXPECT_FALSE(fs::exists(dir_ / "results" / "bench_mapping.csv"));
}

}  // namespace
}  // namespace xcut
