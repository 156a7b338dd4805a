// The perf suite in a tiny configuration: every CSV it writes has the documented columns and finite
// values, the roofline is positive, the force kernel's achieved fraction of its bound is a sane
// number, and a system the scene does not need is never called (exactly zero time). Speed itself
// is never asserted: a slow or busy machine cannot fail these.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "tools/bench/bench.h"
#include "tools/bench/bench_kernel.h"
#include "tools/bench/force_kernel_model.h"
#include "tools/bench/roofline.h"
#include "systems/pipeline.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

/// A CSV as header + rows of cells; `#` lines are comments.
struct Table {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    int column(const std::string& name) const {
        for (size_t i = 0; i < header.size(); ++i)
            if (header[i] == name) return static_cast<int>(i);
        ADD_FAILURE() << "no column " << name;
        return 0;
    }
    double number(size_t row, const std::string& name) const { return std::stod(rows[row][column(name)]); }
    std::string text(size_t row, const std::string& name) const { return rows[row][column(name)]; }
};

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    return cells;
}

Table read_table(const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << path;
    Table t;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        if (t.header.empty()) {
            t.header = split(line);
        } else {
            t.rows.push_back(split(line));
            EXPECT_EQ(t.rows.back().size(), t.header.size()) << path << ": " << line;
        }
    }
    return t;
}

/// Header as expected, at least one row, and every cell of the numeric columns finite and >= 0.
void expect_table(const Table& t, const std::string& header, const std::vector<std::string>& text_columns = {}) {
    std::string joined;
    for (const auto& h : t.header) joined += (joined.empty() ? "" : ",") + h;
    EXPECT_EQ(joined, header);
    EXPECT_FALSE(t.rows.empty());
    for (const auto& row : t.rows)
        for (size_t c = 0; c < row.size() && c < t.header.size(); ++c) {
            if (std::find(text_columns.begin(), text_columns.end(), t.header[c]) != text_columns.end()) continue;
            const double v = std::stod(row[c]);
            EXPECT_TRUE(std::isfinite(v)) << t.header[c] << " = " << row[c];
            EXPECT_GE(v, 0.0) << t.header[c];
        }
}

class BenchPerf : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        options_.scene = std::string(XCUT_SOURCE_DIR) + "/scenes/tissue_block.json";
        options_.sizes = {600};
        options_.steps = 2;
        options_.skip_tets = 600;
        // Small, but each run long enough (milliseconds) that starting the threads does not dominate.
        options_.roofline.triad_doubles = 1L << 20;
        options_.roofline.repeats = 10;
        options_.roofline.fma_iterations = 1'000'000;
        dir_ = fs::temp_directory_path() / ("xcut_bench_perf_" + std::to_string(::getpid()));
        options_.csv = (dir_ / "bench_perf.csv").string();
        rc_ = perf_bench_command(options_);
    }
    static void TearDownTestSuite() { fs::remove_all(dir_); }
    static Table part(const std::string& name) { return read_table(sibling_csv(options_.csv, name)); }

    static inline PerfBenchOptions options_;
    static inline fs::path dir_;
    static inline int rc_ = -1;
};

TEST_F(BenchPerf, StepsTable) {
    ASSERT_EQ(rc_, 0);
    const Table t = read_table(options_.csv);
    expect_table(t, "tets,nodes,threads,steps_per_s,ms_per_step,cg_iter_per_step,force_ms,solver_ms,"
                    "bytes_per_tet_components,bytes_per_tet_rss,speedup,load_average");
    ASSERT_EQ(t.rows.size(), 2u);  // 1 and 2 threads
    EXPECT_GT(t.number(0, "steps_per_s"), 0.0);
    EXPECT_GT(t.number(0, "cg_iter_per_step"), 0.0);
    EXPECT_LT(t.number(0, "bytes_per_tet_components"), 1000.0);
    EXPECT_DOUBLE_EQ(t.number(0, "speedup"), 1.0);
}

TEST_F(BenchPerf, EveryScheduledSystemTimed) {
    const Table t = part("systems");
    expect_table(t, "tets,threads,system,ms_per_step,share_of_step", {"system"});
    std::map<std::string, int> seen;
    double share = 0.0;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        ++seen[t.text(i, "system")];
        if (t.number(i, "threads") == 1) share += t.number(i, "share_of_step");
    }
    EXPECT_EQ(seen["ForceSystem"], 2);
    EXPECT_EQ(seen["SolverSystem"], 2);
    EXPECT_LE(share, 1.0 + 1e-9) << "the systems' shares add up to at most the whole step";
    EXPECT_GT(share, 0.5);
}

TEST_F(BenchPerf, RooflineAndKernel) {
    const Table r = part("roofline");
    expect_table(r, "threads,triad_gbs,peak_gflops,fma_gflops,triad_mib,vector_isa", {"vector_isa"});
    for (size_t i = 0; i < r.rows.size(); ++i) {
        EXPECT_GT(r.number(i, "triad_gbs"), 0.0);
        EXPECT_GT(r.number(i, "peak_gflops"), 0.0);
    }
    const Table k = part("kernel");
    expect_table(k,
                 "kernel,tets,threads,kernel_threads,ms,newton_iterations,flops_per_element,bytes_per_element,intensity,achieved_gflops,"
                 "achieved_gbs,peak_gflops,triad_gbs,bound_gflops,bound,fraction_of_bound",
                 {"kernel", "bound"});
    ASSERT_EQ(k.rows.size(), 4u);  // force and cg_product at 1 and 2 threads
    for (size_t i = 0; i < k.rows.size(); ++i) {
        const double f = k.number(i, "fraction_of_bound");
        EXPECT_GT(f, 0.0);
        EXPECT_LE(f, 1.5) << "a kernel cannot beat its roofline by half (counts or timing wrong)";
        if (k.text(i, "kernel") == "force") {
            EXPECT_GE(k.number(i, "newton_iterations"), 1.0);
        }
        EXPECT_EQ(k.number(i, "kernel_threads"), 1.0) << "600 tets: below the parallel threshold";
        const std::string bound = k.text(i, "bound");
        EXPECT_TRUE(bound == "compute" || bound == "memory") << bound;
    }
}

TEST_F(BenchPerf, CutUpdateAgainstSize) {
    const Table t = part("cut");
    expect_table(t, "search,tets,quads,splits,cut_again,quad_p50_ms,quad_p99_ms,update_p50_ms,update_p99_ms,delay_p50_s,"
                   "delay_p99_s,update_max_ms,worst_cutter_ms,worst_enrichment_ms",
                 {"search"});
    EXPECT_GT(t.number(0, "splits"), 0.0);
    EXPECT_GE(t.number(0, "update_p99_ms"), t.number(0, "update_p50_ms"));
    EXPECT_GE(t.number(0, "update_max_ms"), t.number(0, "update_p99_ms"));
}

TEST_F(BenchPerf, SkippedSystemsCostExactlyZero) {
    const Table t = part("skip");
    expect_table(t, "scene,system,scheduled,calls,ms_per_step,step_ms", {"scene", "system"});
    std::map<std::string, std::map<std::string, bool>> scheduled;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const bool on = t.number(i, "scheduled") == 1.0;
        scheduled[t.text(i, "scene")][t.text(i, "system")] = on;
        if (!on) {
            EXPECT_EQ(t.number(i, "calls"), 0.0) << t.text(i, "system");
            EXPECT_EQ(t.number(i, "ms_per_step"), 0.0) << t.text(i, "system") << " is skipped: it must cost nothing";
        } else {
            EXPECT_EQ(t.number(i, "calls"), options_.steps) << t.text(i, "system");
        }
    }
    for (const char* s : {"ToolSystem", "CutSystem", "CollisionSystem", "MappingSystem"}) {
        EXPECT_TRUE(scheduled["with"][s]) << s;
        EXPECT_FALSE(scheduled["without"][s]) << s;
    }
    EXPECT_TRUE(scheduled["without"]["ForceSystem"]);
    EXPECT_TRUE(scheduled["without"]["SolverSystem"]);
}

std::string read_text(const fs::path& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// tools/report/benchmarks_report.py on the tiny run's CSVs: it fills the perf markers, keeps the text
// around them, leaves a section whose CSV is missing as it is, and appends a suite it has no
// markers for.
TEST_F(BenchPerf, ReportRegeneratesOnlyBetweenMarkers) {
    if (std::system("python3 -c 'import csv' > /dev/null 2>&1") != 0) GTEST_SKIP() << "no python3";
    const fs::path doc = dir_ / "BENCHMARKS.md";
    {
        std::ofstream out(doc);
        out << "# Benchmarks\nhand-written intro\n<!-- generated: perf -->\nold table\n<!-- end -->\n"
               "hand-written analysis\n<!-- generated: accuracy -->\nkept accuracy table\n<!-- end -->\n";
        std::ofstream extra(dir_ / "bench_extra.csv");
        extra << "size,value\n1,2.5\n";
    }
    const std::string cmd = "python3 " + std::string(XCUT_SOURCE_DIR) + "/tools/report/benchmarks_report.py --no-plots --results " +
                            dir_.string() + " --doc " + doc.string() + " > /dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const std::string text = read_text(doc);
    EXPECT_NE(text.find("hand-written intro"), std::string::npos);
    EXPECT_NE(text.find("hand-written analysis"), std::string::npos);
    EXPECT_EQ(text.find("old table"), std::string::npos);
    EXPECT_NE(text.find("### Targets"), std::string::npos);
    EXPECT_NE(text.find("### Kernels against the roofline"), std::string::npos);
    EXPECT_NE(text.find("kept accuracy table"), std::string::npos) << "no bench_accuracy.csv: section left as it is";
    EXPECT_NE(text.find("<!-- generated: extra -->"), std::string::npos) << "a new suite gets a section";
    EXPECT_LT(text.find("hand-written analysis"), text.find("<!-- generated: extra -->"));
    fs::remove(dir_ / "bench_extra.csv");
}

TEST(BenchRoofline, MeasuresPositiveFigures) {
    EXPECT_GT(triad_bandwidth_gbs(1, 1 << 16, 1), 0.0);
    EXPECT_GT(multiply_add_peak_gflops(1, 10000, false), 0.0);
    EXPECT_GE(multiply_add_peak_gflops(1, 10000, true), 0.0);
    EXPECT_EQ(vector_isa().find(','), std::string::npos) << "written into a CSV cell";
}

TEST(BenchForceKernel, RestShapeTakesOneNewtonStep) {
    // At rest F = I: the first Newton step returns I unchanged and stops.
    const Scene scene = sized_scene(std::string(XCUT_SOURCE_DIR) + "/scenes/tissue_block.json", 600);
    auto sim = make_simulation(scene, false);
    EXPECT_DOUBLE_EQ(mean_newton_iterations(sim->world), 1.0);
    const ForceKernelCounts c = force_system_counts(1.0, 0.2);
    EXPECT_GT(c.intensity(), 0.0);
    EXPECT_LT(c.intensity(), 10.0);
}

}  // namespace
}  // namespace xcut
