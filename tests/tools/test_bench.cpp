// The benchmarks run in a tiny configuration: their figures are finite and positive and their
// CSVs have the documented columns (run time itself is never asserted). The perf suite's tests are
// in test_bench_perf.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <fstream>

#include "tools/bench/bench_cut.h"
#include "tools/bench/bench_cutstep.h"
#include "tools/bench/bench_mapping.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> csv_lines(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

void expect_finite_positive_row(const std::string& row) {
    std::stringstream ss(row);
    for (std::string cell; std::getline(ss, cell, ',');) {
        const double v = std::stod(cell);
        EXPECT_TRUE(std::isfinite(v)) << row;
        EXPECT_GE(v, 0.0) << row;
    }
}

TEST(Bench, CutSuiteTinyRun) {
    CutBenchOptions o;
    o.sizes = {1500};
    o.speed = 0.2;
    o.csv = (fs::temp_directory_path() / ("xcut_bench_cut_" + std::to_string(::getpid()) + ".csv")).string();
    ASSERT_EQ(cut_bench_command(o), 0);
    const auto lines = csv_lines(o.csv);
    ASSERT_EQ(lines.size(), 4u);  // header, neighbourhood search, BVH search, cut again
    EXPECT_EQ(lines[0],
              "search,tets,quads,splits,cut_again,quad_p50_ms,quad_p99_ms,update_p50_ms,update_p99_ms,delay_p50_s,delay_p99_s,"
              "update_max_ms,worst_cutter_ms,worst_enrichment_ms");
    EXPECT_EQ(lines[1].rfind("neighbourhood,", 0), 0u);
    EXPECT_EQ(lines[2].rfind("bvh,", 0), 0u);
    EXPECT_EQ(lines[3].rfind("recut,", 0), 0u);
    for (size_t i = 1; i < lines.size(); ++i) expect_finite_positive_row(lines[i].substr(lines[i].find(',') + 1));
    const auto rows = run_cut_bench(o);
    EXPECT_GT(rows[0].splits, 0) << "the blade cuts the block";
    EXPECT_GT(rows[0].quads, 1);
    EXPECT_GE(rows[0].update_max_ms, rows[0].update_p99_ms) << "the worst step bounds every percentile";
    EXPECT_NEAR(rows[0].worst_cutter_ms + rows[0].worst_enrichment_ms, rows[0].update_max_ms, 1e-9 * rows[0].update_max_ms)
        << "the worst step's two parts make it up";
    EXPECT_GT(rows[0].worst_cutter_ms, 0.0);
    o.bvh_every_quad = true;
    EXPECT_EQ(run_cut_bench(o)[0].splits, rows[0].splits) << "both searches find the same elements";
    EXPECT_EQ(rows[0].cut_again, 0) << "one scalpel cuts each element once";
    o.bvh_every_quad = false;
    o.recut = true;
    const CutBenchRow again = run_cut_bench(o)[0];
    EXPECT_GT(again.cut_again, 0) << "the second and third scalpels cut the elements about the crossing again";
    EXPECT_GT(again.splits, 2 * rows[0].splits) << "three scalpels split more than twice what one does";
    fs::remove(o.csv);
}

TEST(Bench, CutStepSuiteTinyRun) {
    // The suite reads the shipped scenes by their paths in the checkout, as `xcut bench` run there does.
    struct InSource {
        fs::path was = fs::current_path();
        InSource() { fs::current_path(XCUT_SOURCE_DIR); }
        ~InSource() { fs::current_path(was); }
    } in_source;
    CutStepBenchOptions o;
    o.tiny = true, o.progress = false;
    o.csv = (fs::temp_directory_path() / ("xcut_bench_cutstep_" + std::to_string(::getpid()) + ".csv")).string();
    ASSERT_EQ(cutstep_bench_command(o), 0);
    const auto lines = csv_lines(o.csv);
    ASSERT_EQ(lines.size(), 5u);  // header; skin and block, quiet and beside a busy process
    EXPECT_EQ(lines[0].rfind("case,load,method,tets,steps,dofs_end,median_ms,p99_ms,max_ms,p99_over_median,", 0), 0u);
    const auto rows = run_cutstep_bench(o);
    ASSERT_EQ(rows.size(), 4u);
    for (const CutStepBenchRow& r : rows) {
        EXPECT_TRUE(r.failure.empty()) << r.failure;
        EXPECT_GT(r.split_steps, 0) << r.case_name << ": the blade splits elements";
        EXPECT_GT(r.median_ms, 0.0);
        EXPECT_GE(r.max_ms, r.p99_ms);
        EXPECT_GE(r.p99_ms, r.median_ms);
        EXPECT_GE(r.split_max_ms, r.split_median_ms);
        EXPECT_GT(r.cut_from, 0);
        EXPECT_GE(r.cut_to - r.cut_from + 1, r.split_steps) << "the cut spans every step that split";
        EXPECT_LE(r.cut_to, r.steps);
        EXPECT_GE(r.cut_max_ms, r.split_max_ms) << "the steps that split are the cut's";
        EXPECT_LE(r.cut_max_ms, r.max_ms);
        EXPECT_GE(r.cut_max_ms, r.cut_p99_ms);
        EXPECT_GE(r.cg_split_max, 1.0);
        EXPECT_EQ(r.builds, 0) << r.case_name << ": the cholesky factor is renewed off the step, never in it";
    }
    EXPECT_EQ(rows[2].load, "busy");
    EXPECT_EQ(rows[0].case_name, rows[2].case_name);
    EXPECT_EQ(rows[0].split_steps, rows[2].split_steps) << "the load changes the times, not what is cut";
    fs::remove(o.csv);
}

TEST(Bench, MappingSuiteTinyRun) {
    MappingBenchOptions o;
    o.subdivisions = {0};
    o.repeats = 2;
    o.csv = (fs::temp_directory_path() / ("xcut_bench_map_" + std::to_string(::getpid()) + ".csv")).string();
    ASSERT_EQ(mapping_bench_command(o), 0);
    const auto lines = csv_lines(o.csv);
    ASSERT_EQ(lines.size(), 3u);  // header, 1 and 2 threads
    EXPECT_EQ(lines[0], "subdivisions,vertices,triangles,threads,update_ms,ns_per_vertex,rebind_us_per_split");
    for (size_t i = 1; i < lines.size(); ++i) expect_finite_positive_row(lines[i]);
    fs::remove(o.csv);
}

}  // namespace
}  // namespace xcut
