// `xcut bench --suite accuracy` in its tiny configuration (docs/verification.md problems 3, 5, 6): the CSV
// has the documented columns and finite values, the error decreases with resolution for every
// series, and the pieces the suite stands on (the conforming reference mesh and its cache, probes on
// the right side of a crack, the handbook CMOD) are checked on their own. Run time is never asserted.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "systems/cut/crack_tip_system.h"
#include "tools/studies/accuracy_problems.h"
#include "tools/bench/bench_accuracy.h"
#include "tools/studies/crack_reference.h"

namespace xcut {
namespace {

namespace fs = std::filesystem;

std::string cache_dir() { return std::string(XCUT_BUILD_DIR) + "/accuracy_cache"; }

std::vector<ReferenceNote> tiny_notes;

/// The tiny suite, run once for every test below.
const std::vector<AccuracyRow>& tiny_rows() {
    static const std::vector<AccuracyRow> rows = [] {
        AccuracyBenchOptions o = AccuracyBenchOptions::tiny();
        o.cache_dir = cache_dir();
        return run_accuracy_bench(o, &tiny_notes);
    }();
    return rows;
}

bool calculix_installed() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

std::vector<std::string> split_csv(const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    return cells;
}

TEST(AccuracyBench, CsvHasTheColumnsAndFiniteValues) {
    const auto& rows = tiny_rows();
    const std::string csv = (fs::temp_directory_path() / ("xcut_bench_accuracy_" + std::to_string(::getpid()) + ".csv")).string();
    const std::vector<std::string> summary = accuracy_summary(rows, tiny_notes);
    write_accuracy_csv(csv, rows, summary);
    std::ifstream in(csv);
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    EXPECT_EQ(line, "problem,cutter,resolution,element_size_m,dofs,split,run_time_s,cpu_time_s,newton,cg_iterations,value_m,"
                    "reference_m,error");
    size_t count = 0, comments = 0;
    while (std::getline(in, line)) {
        if (line.rfind("# ", 0) == 0) {
            ++comments;
            continue;
        }
        EXPECT_EQ(comments, 0u) << "the summary comes after the rows";
        const auto cells = split_csv(line);
        ASSERT_EQ(cells.size(), 13u) << line;
        EXPECT_TRUE(cells[1] == "xfem" || cells[1] == "xfem_tip" || cells[1] == "snap" || cells[1] == "xfem-quadratic" ||
                    cells[1] == "uncut")
            << line;
        for (size_t k = 0; k < cells.size(); ++k) {
            if (k == 1) continue;
            const double v = std::stod(cells[k]);
            EXPECT_TRUE(std::isfinite(v)) << line;
            EXPECT_GE(v, 0.0) << line;
        }
        ++count;
    }
    const AccuracyBenchOptions o = AccuracyBenchOptions::tiny();
    EXPECT_EQ(count, o.cantilever_levels.size() + 3 * o.block_levels.size() + 3 * o.plate_levels.size() +
                         o.plate_quadratic_levels.size());
    EXPECT_EQ(comments, summary.size()) << "every summary line, as a comment";
    // The references' lines; problem 3; for 5 and 6 each run against the other cutter and who wins
    // where; 5's front-enriched runs against snapping and its target; 6's tip-enriched runs against
    // snapping and its target; 6's quadratic runs against the linear XFEM and their target; 6's
    // finest per cutter.
    EXPECT_EQ(summary.size(), tiny_notes.size() + 1u + (2 * o.block_levels.size() + 2) + (2 * o.plate_levels.size() + 1) +
                                  (o.block_levels.size() + 1) + (o.plate_levels.size() + 1) +
                                  (o.plate_quadratic_levels.size() + 1) + 3u);
    for (int problem : {3, 5, 6}) {
        const auto it = std::find_if(tiny_notes.begin(), tiny_notes.end(), [problem](const ReferenceNote& n) { return n.problem == problem; });
        EXPECT_NE(it, tiny_notes.end()) << "problem " << problem << " says what it was scored against";
    }
    fs::remove(csv);
}

// Each run against the other cutter's front at its own CPU time, interpolated log-log; a run
// outside the other's CPU-time range is said to be, not scored; no average verdict. Wall time plays
// no part (here it runs against CPU time: a loaded machine).
TEST(AccuracyBench, FrontsAreComparedRunByRunAtEqualTime) {
    auto row = [](const char* cutter, int level, double cpu_s, double error) {
        AccuracyRow r;
        r.problem = 5, r.cutter = cutter, r.resolution = level, r.cpu_s = cpu_s, r.error = error;
        r.run_s = 1.0 / cpu_s;
        return r;
    };
    const std::vector<AccuracyRow> rows = {row("xfem", 4, 0.1, 0.1), row("xfem", 8, 1.0, 0.02), row("xfem", 16, 10.0, 0.01),
                                           row("snap", 4, 0.05, 0.3), row("snap", 8, 2.0, 0.01), row("snap", 16, 20.0, 0.001)};
    const auto cmp = compare_fronts(rows, 5);
    ASSERT_EQ(cmp.size(), 6u);
    // xfem at 1 s: snapping between 0.05 s (30 %) and 2 s (1 %), log-log: t = log(20) / log(40).
    const double t = std::log(20.0) / std::log(40.0);
    const double snap_at_1s = std::exp((1 - t) * std::log(0.3) + t * std::log(0.01));
    EXPECT_NEAR(cmp[1].other_error, snap_at_1s, 1e-12);
    EXPECT_NEAR(cmp[1].ratio, 0.02 / snap_at_1s, 1e-12);
    EXPECT_GT(cmp[1].ratio, 1.0) << "snapping is the more accurate at 1 s";
    EXPECT_LT(cmp[0].ratio, 1.0) << "XFEM at 0.1 s beats snapping's 0.05-2 s line there";
    EXPECT_EQ(cmp[5].ratio, 0.0) << "snapping at 20 s is past XFEM's longest run";
    const auto lines = accuracy_summary(rows);
    bool wins = false;
    for (const std::string& l : lines) {
        EXPECT_EQ(l.find("mean"), std::string::npos) << l;
        if (l.find("problem 5: at equal CPU time XFEM is the more accurate at xfem 4; snapping at xfem 8, xfem 16, snap 8") !=
            std::string::npos)
            wins = true;
    }
    EXPECT_TRUE(wins) << "the levels where each cutter wins are stated";
    EXPECT_NE(std::find(lines.begin(), lines.end(),
                        "problem 5 target (XFEM at or below snapping's front wherever its error is under 10 %): NOT met: "
                        "level 8 at 1.06 x, level 16 at 5.00 x"),
              lines.end());
}

// The independent references (CalculiX, quadratic elements, extrapolated) against the closed forms
// they must agree with where those hold: beam theory with shear for the slender cantilever, the
// handbook's CMOD (quoted to about 0.5 %) for the plate; each with a small error estimate.
TEST(AccuracyBench, CalculixReferencesAgreeWithTheClosedForms) {
    if (!calculix_installed()) GTEST_SKIP() << "CalculiX (calculix-ccx) is not installed";
    tiny_rows();  // the tiny suite has computed and cached them
    std::map<int, std::string> lines;
    for (const ReferenceNote& n : tiny_notes) lines[n.problem] += n.line;
    for (int problem : {3, 5, 6}) EXPECT_NE(lines[problem].find("CalculiX"), std::string::npos) << lines[problem];
    double cantilever = 0.0, cmod = 0.0;
    for (const AccuracyRow& r : tiny_rows()) {
        if (r.problem == 3) cantilever = r.reference;
        if (r.problem == 6) cmod = r.reference;
    }
    EXPECT_NEAR(cantilever / cantilever_reference(CantileverSpec{}), 1.0, 1e-3);
    EXPECT_NEAR(cmod / edge_crack_reference_cmod(EdgeCrackSpec{}), 1.0, 5e-3);
    EXPECT_NE(lines[6].find("CalculiX CPS8"), std::string::npos) << lines[6];
    // The crack-length sweep: the tiny configuration's a / W = 0.375, both cutters, against its own reference.
    const size_t sweep = lines[6].find("problem 6 at a/W = 0.375 (level 64");
    ASSERT_NE(sweep, std::string::npos) << lines[6];
    EXPECT_NE(lines[6].find(" xfem ", sweep), std::string::npos) << lines[6];
    EXPECT_NE(lines[6].find(" snap ", sweep), std::string::npos) << lines[6];
    EXPECT_EQ(lines[6].find("NOT scored"), std::string::npos) << lines[6];
    // The blade-stop sweep: each cutter's errors at the tiny configuration's 3 stops, and their spread.
    for (const char* c : {"xfem", "progressive", "snap"})
        EXPECT_NE(lines[6].find(std::string("problem 6 blade stops (") + c + ", level 16, 3 stops"), std::string::npos)
            << lines[6];
    // Problem 5's blade-stop sweep (2 stops at level 8): the crack the semi front leaves ends on the
    // last fully crossed elements, so its error moves with the stop; the front at the blade's stop
    // moves less (the record, level 16: a spread of 7.0 points against 0.34).
    std::map<std::string, double> spread;
    for (const char* c : {"xfem", "xfem_tip", "snap"}) {
        const std::string head = std::string("problem 5 blade stops (") + c + ", level 8, 2 stops";
        const size_t at = lines[5].find(head);
        ASSERT_NE(at, std::string::npos) << lines[5];
        spread[c] = std::stod(lines[5].substr(lines[5].find("spread ", at) + 7));
    }
    EXPECT_LT(spread["xfem_tip"], 0.5 * spread["xfem"]) << lines[5];
    EXPECT_EQ(lines[5].find("NOT scored"), std::string::npos) << lines[5];
}

/// CMOD of the tiny plate (16 cells across W) cut by `cutter` from its left edge to x = stop [m].
double plate_cmod(double stop, bool progressive, int* split = nullptr) {
    const EdgeCrackSpec spec;
    World w = edge_crack_world(spec, 16);
    EdgeCrackSpec cut = spec;
    cut.crack = stop;
    const int s = cut_with_polygon(w, edge_crack_segment(cut), progressive);
    if (split) *split = s;
    const Eigen::VectorXd load = edge_crack_load(w, spec);
    EXPECT_TRUE(solve_equilibrium(w, load).converged);
    return edge_crack_cmod(w, spec);
}

// A blade stopped inside a cell: the semi-progressive rule ends the crack at the last element it
// crossed, the progressive front splits the element it stopped in as a tip element (its far node
// held), so its crack mouth opens more than the semi front's and less than a crack through the
// whole cell.
// CalculiX solves its plane-stress quadrilaterals as a layer of 3D elements as thick as their
// section, held together through it: near the crack tip a layer as thick as the plate's own 1 mm
// (W / 40) is stiffer than plane stress, and its CMOD was 0.18 % low. The plate's deck is drawn with
// a section thin enough to be in the plane-stress limit: thinner still changes nothing measurable.
TEST(AccuracyBench, ThePlatesReferenceIsInThePlaneStressLimit) {
    if (!calculix_installed()) GTEST_SKIP() << "CalculiX (calculix-ccx) is not installed";
    const EdgeCrackSpec e;
    const nlohmann::json plate = {{"width", e.width},   {"height", e.height}, {"crack", e.crack},
                                  {"stress", e.stress}, {"young", e.young},   {"poisson", e.poisson},
                                  {"density", e.density}, {"thickness", e.thickness}};
    const std::string cache = (std::filesystem::temp_directory_path() / "xcut_plane_stress_section").string();
    std::filesystem::remove_all(cache);
    auto cmod_at_level_20 = [&](double section_fraction) {
        nlohmann::json p = plate;
        if (section_fraction > 0.0) p["section_fraction"] = section_fraction;
        const ExternalReference r = calculix_reference(6, p, {10, 20}, cache);
        EXPECT_TRUE(r.available) << r.why;
        return r.available && r.level_value.size() == 2 ? r.level_value[1] : 0.0;
    };
    const double deck = cmod_at_level_20(0.0), thinner = cmod_at_level_20(2.5e-5), own = cmod_at_level_20(e.thickness / e.width);
    ASSERT_GT(deck, 0.0);
    EXPECT_NEAR(thinner / deck, 1.0, 2e-5) << "the deck's section is in the plane-stress limit";
    EXPECT_LT(own / deck, 1.0 - 1e-3) << "a section of the plate's own thickness is stiffer";
    std::filesystem::remove_all(cache);
}

TEST(AccuracyBench, AProgressiveCutOpensTheElementTheBladeStoppedIn) {
    const EdgeCrackSpec spec;
    const double h = spec.width / 16;
    int at_grid_line = 0, semi_split = 0, progressive_split = 0;
    const double grid_line = plate_cmod(spec.crack, false, &at_grid_line);
    const double semi = plate_cmod(spec.crack + 0.25 * h, false, &semi_split);
    const double progressive = plate_cmod(spec.crack + 0.25 * h, true, &progressive_split);
    const double whole_cell = plate_cmod(spec.crack + h, false);
    // A quarter into the cell, the blade has not reached the cell's diagonal (at its middle, y = H / 2).
    EXPECT_EQ(semi_split, at_grid_line) << "the semi front ends the crack at x = a";
    EXPECT_EQ(progressive_split, at_grid_line + 1) << "and the triangle the blade entered";
    EXPECT_NEAR(semi, grid_line, 1e-12 * semi);
    EXPECT_GT(progressive, semi * (1 + 1e-4));
    EXPECT_LT(progressive, whole_cell * (1 - 1e-4));
}

// A quick or partial run writes its own CSV beside the record, never over it.
TEST(AccuracyBench, AQuickRunNeverOverwritesTheRecord) {
    const fs::path dir = fs::temp_directory_path() / ("xcut_bench_quick_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string cmd = "cd " + dir.string() + " && " + XCUT_BINARY +
                            " bench --suite accuracy --tiny --problems 3 --no-plots --cache-dir cache > out.txt 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_TRUE(fs::exists(dir / "results" / "bench_accuracy_quick.csv"));
    EXPECT_FALSE(fs::exists(dir / "results" / "bench_accuracy.csv"));
    std::ifstream out(dir / "out.txt");
    std::stringstream ss;
    ss << out.rdbuf();
    EXPECT_NE(ss.str().find("not the record results/bench_accuracy.csv"), std::string::npos) << ss.str();
    fs::remove_all(dir);
}

TEST(AccuracyBench, ErrorDecreasesWithResolutionForBothCutters) {
    std::map<std::pair<int, std::string>, std::vector<const AccuracyRow*>> series;
    for (const AccuracyRow& r : tiny_rows()) series[{r.problem, r.cutter}].push_back(&r);
    const std::set<std::pair<int, std::string>> expected = {{3, "uncut"}, {5, "xfem"}, {5, "xfem_tip"}, {5, "snap"}, {6, "xfem"},
                                                             {6, "xfem_tip"}, {6, "snap"}, {6, "xfem-quadratic"}};
    ASSERT_EQ(series.size(), expected.size());
    for (const auto& [key, list] : series) {
        EXPECT_TRUE(expected.count(key)) << key.first << " " << key.second;
        for (size_t k = 1; k < list.size(); ++k) {
            EXPECT_GT(list[k]->resolution, list[k - 1]->resolution);
            EXPECT_GT(list[k]->dofs, list[k - 1]->dofs);
            // (Problem 5's front zone of two cells holds the whole block at level 4, 10 mm cells:
            // 7.8 % there against 9.5 % at level 8, measured. From there on it shrinks with the cells.)
            if (key == std::pair<int, std::string>{5, "xfem_tip"} && list[k - 1]->resolution == 4) continue;
            EXPECT_LT(list[k]->error, list[k - 1]->error)
                << "problem " << key.first << " " << key.second << " level " << list[k]->resolution;
        }
        if (key.first != 3) {
            for (const AccuracyRow* r : list) EXPECT_GT(r->split, 0) << "the cut split elements";
        }
    }
}

TEST(AccuracyBench, TheEnrichedTipCutsTheCrackOpeningsError) {
    // Problem 6 (CMOD against CalculiX's reference): with the tip's branch functions XFEM's error is
    // a fraction of plain XFEM's at every level, and within 1 % at 64 cells (measured with the zone at
    // five cells: 1.10 % at 32, 0.48 % at 64; the record -0.84 % at 40 cells against -7.9 %; docs/xfem.md).
    std::map<int, std::map<std::string, double>> error;
    for (const AccuracyRow& r : tiny_rows())
        if (r.problem == 6 && r.cutter != "xfem-quadratic") error[r.resolution][r.cutter] = r.error;
    ASSERT_EQ(error.size(), AccuracyBenchOptions::tiny().plate_levels.size());
    for (auto& [level, e] : error) {
        EXPECT_LT(e["xfem_tip"], 0.3 * e["xfem"]) << level;
        std::printf("level %d: xfem %.3f %%, xfem_tip %.3f %%\n", level, 100 * e["xfem"], 100 * e["xfem_tip"]);
        if (level >= 64) {
            EXPECT_LT(e["xfem_tip"], 0.01) << level;
        }
    }
}

TEST(AccuracyBench, TheEnrichedFrontCutsTheSlitBlocksError) {
    // Problem 5 (displacements at the samples against CalculiX's reference): with the front's branch
    // functions (3D, over the front's elements) XFEM's error is below plain XFEM's at every level
    // (measured: 0.53, 0.68, 0.69 x at 4, 8, 12 cells).
    std::map<int, std::map<std::string, double>> error;
    for (const AccuracyRow& r : tiny_rows())
        if (r.problem == 5) error[r.resolution][r.cutter] = r.error;
    ASSERT_EQ(error.size(), AccuracyBenchOptions::tiny().block_levels.size());
    for (auto& [level, e] : error) {
        std::printf("level %d: xfem %.3f %%, xfem_tip %.3f %%, snap %.3f %%\n", level, 100 * e["xfem"], 100 * e["xfem_tip"],
                    100 * e["snap"]);
        EXPECT_LT(e["xfem_tip"], 0.8 * e["xfem"]) << level;
    }
}

TEST(AccuracyBench, EdgeCrackOpeningApproachesTheHandbook) {
    // Tada, Paris & Irwin, SENT: a / W = 1/2 gives V1 = 2 (1.46 + 3.42 (1 - sqrt(2)/2)) = 4.9233896.
    const EdgeCrackSpec spec;
    EXPECT_NEAR(edge_crack_reference_cmod(spec), 4.0 * 0.01 * 0.02 / 1e4 * 4.9233896, 1e-6 * 3.94e-7);
    // docs/verification.md holds the converged opening to 5 %: the tiny configuration's finest level (64
    // cells across W) reaches it with both cutters (measured -4.6 % XFEM, -3.5 % snapping; below the
    // handbook: linear elements without tip functions are stiff at the tip, and converge from below).
    for (const char* cutter : {"xfem", "snap"}) {
        const AccuracyRow* finest = nullptr;
        for (const AccuracyRow& r : tiny_rows())
            if (r.problem == 6 && r.cutter == cutter && (!finest || r.resolution > finest->resolution)) finest = &r;
        ASSERT_NE(finest, nullptr);
        EXPECT_LT(finest->error, 0.05) << cutter;
        EXPECT_LT(finest->value, finest->reference) << cutter;
    }
}

// A tip's zone that holds the crack's mouth: the opening is read through the enriched field there
// (crack_enrichment_at), not the elements' linear interpolation alone. At 10 cells with a zone of
// 0.6 W (the mouth 0.5 W from the tip) the CMOD is within 3 % of the handbook's (measured -1.8 %
// against CalculiX's reference; read from the nodes alone it was -45 %), and the larger zone is
// closer than one of 0.4 W that stops short of the mouth.
TEST(AccuracyBench, TheMouthsOpeningIsReadThroughTheTipsFieldWhenTheZoneHoldsIt) {
    const EdgeCrackSpec spec;
    const auto cmod = [&](double radius, bool& mouth_enriched) {
        World w = edge_crack_world(spec, 10);
        const std::vector<Vec3> segment = edge_crack_segment(spec);
        cut_with_polygon(w, segment);
        enrich_crack_tip(w, segment.back(), segment.back() - segment.front(), TipZone{radius});
        const Probe mouth = locate_points(w, {Vec3(0.0, 0.5 * spec.height + 1e-6 * spec.width, 0.0)})[0];
        mouth_enriched = std::count(w.tips.element.begin(), w.tips.element.end(), mouth.element) > 0;
        const Eigen::VectorXd load = edge_crack_load(w, spec);
        EXPECT_TRUE(solve_equilibrium(w, load).converged);
        return edge_crack_cmod(w, spec);
    };
    bool wide_holds = false, narrow_holds = true;
    const double wide = cmod(0.6 * spec.width, wide_holds), narrow = cmod(0.4 * spec.width, narrow_holds);
    ASSERT_TRUE(wide_holds);
    ASSERT_FALSE(narrow_holds);
    const double reference = edge_crack_reference_cmod(spec);
    std::printf("CMOD / handbook - 1: zone 0.6 W %+.3f %%, 0.4 W %+.3f %%\n", 100 * (wide / reference - 1),
                100 * (narrow / reference - 1));
    EXPECT_NEAR(wide / reference, 1.0, 0.03);
    EXPECT_LT(std::abs(wide / reference - 1.0), std::abs(narrow / reference - 1.0));
}

// Problem 6 on 6-node triangles: the load is the edges' consistent one (1/6, 2/3, 1/6 of sigma t L
// along a quadratic edge), so the uncut plate stretches exactly as the plane-stress closed form says,
// u_y(H) - u_y(0) = sigma H / E and u_x(W) - u_x(0) = -nu sigma W / E (a uniform strain, which the
// element holds exactly; the corotation's own nonlinearity is of the order of the strain, 1e-6).
// Cut, its CMOD converges from below and at 8 cells is closer than the linear XFEM's at 16.
TEST(AccuracyBench, TheQuadraticPlateStretchesAsThePlaneStressClosedForm) {
    const EdgeCrackSpec spec;
    World w = edge_crack_world(spec, 4, true);
    ASSERT_TRUE(w.quadratic.planar);
    const Eigen::VectorXd load = edge_crack_load(w, spec);
    ASSERT_TRUE(solve_equilibrium(w, load).converged);
    const auto p = locate_points(w, {Vec3(0.3 * spec.width, 0.0, 0.0), Vec3(0.3 * spec.width, spec.height, 0.0),
                                     Vec3(0.0, 0.3 * spec.height, 0.0), Vec3(spec.width, 0.3 * spec.height, 0.0)});
    const double stretch = probe_displacement(w, p[1]).y() - probe_displacement(w, p[0]).y();
    const double narrow = probe_displacement(w, p[3]).x() - probe_displacement(w, p[2]).x();
    const double strain = spec.stress / spec.young;
    EXPECT_NEAR(stretch, strain * spec.height, 1e-5 * strain * spec.height);
    EXPECT_NEAR(narrow, -spec.poisson * strain * spec.width, 1e-5 * strain * spec.width);
    std::map<std::string, std::map<int, const AccuracyRow*>> plate;
    for (const AccuracyRow& r : tiny_rows())
        if (r.problem == 6) plate[r.cutter][r.resolution] = &r;
    ASSERT_EQ(plate["xfem-quadratic"].size(), AccuracyBenchOptions::tiny().plate_quadratic_levels.size());
    const AccuracyRow& q8 = *plate["xfem-quadratic"].at(8);
    std::printf("6-node XFEM at 8 cells: %.3f %%, 3-node at 16: %.3f %%\n", 100 * q8.error, 100 * plate["xfem"].at(16)->error);
    EXPECT_LT(q8.value, q8.reference);
    EXPECT_LT(q8.error, 0.8 * plate["xfem"].at(16)->error);
    EXPECT_LT(q8.error, plate["xfem-quadratic"].at(4)->error);
}

TEST(AccuracyBench, ConformingReferenceDuplicatesTheCutPartOfThePlane) {
    const CutBlockSpec spec;
    const int n = 8;  // 5 mm cells: the plane x = cut_x splits the x range into 4 + 4 cells
    const MeshData mesh = generate_cracked_block(spec, n);
    std::map<std::array<long, 3>, int> at;  // nodes per position (0.1 um)
    for (const Vec3& p : mesh.points) ++at[{std::lround(p.x() * 1e7), std::lround(p.y() * 1e7), std::lround(p.z() * 1e7)}];
    int doubled = 0;
    for (const auto& [pos, count] : at) {
        EXPECT_LE(count, 2);
        if (count == 2) {
            ++doubled;
            EXPECT_EQ(pos[0], std::lround(spec.cut_x * 1e7)) << "only the cut plane is doubled";
            EXPECT_GT(pos[2], std::lround((spec.size.z() - spec.depth) * 1e7)) << "only above the crack front";
        }
    }
    // Nodes on the plane above the front: 2 rows along y (B = 5 mm, one cell) x 2 levels above z = 10 mm.
    EXPECT_EQ(doubled, 2 * 2);
    // No element spans the cut part of the plane: an element beyond it never uses a node of the near side.
    for (const auto& t : mesh.cells) {
        double cx = 0.0;
        for (int a = 0; a < 4; ++a) cx += 0.25 * mesh.points[t[a]].x();
        for (int a = 0; a < 4; ++a) {
            const Vec3& p = mesh.points[t[a]];
            if (std::abs(p.x() - spec.cut_x) > 1e-12 || p.z() <= spec.size.z() - spec.depth + 1e-12) continue;
            const bool copy = t[a] >= static_cast<int>(mesh.points.size()) - doubled;
            EXPECT_EQ(copy, cx > spec.cut_x);
        }
    }
}

TEST(AccuracyBench, ReferenceIsCachedAndReread) {
    CutBlockSpec spec;
    spec.pull = 1.7e-5;  // a key of its own, so this test computes it
    const std::string dir = (fs::temp_directory_path() / ("xcut_acc_cache_" + std::to_string(::getpid()))).string();
    const ReferenceField a = cut_block_reference(spec, 8, dir);
    EXPECT_FALSE(a.from_cache);
    ASSERT_TRUE(fs::exists(a.path));
    const ReferenceField b = cut_block_reference(spec, 8, dir);
    EXPECT_TRUE(b.from_cache);
    ASSERT_EQ(a.displacement.size(), b.displacement.size());
    for (size_t k = 0; k < a.displacement.size(); ++k) EXPECT_EQ(a.displacement[k], b.displacement[k]) << "bit-exact";
    EXPECT_EQ(a.dofs, b.dofs);
    // The lips open: the pull separates the sample pairs straddling the cut.
    const auto& u = a.displacement;
    const size_t lips = cut_block_samples(spec).size() - 8;
    for (size_t k = lips; k < u.size(); k += 2) EXPECT_GT(u[k + 1].x() - u[k].x(), 0.1 * spec.pull);
    const ReferenceField c = cut_block_reference(spec, 12, dir);  // another resolution: another file
    EXPECT_FALSE(c.from_cache);
    EXPECT_NE(c.path, a.path);
    fs::remove_all(dir);
}

TEST(AccuracyBench, ProbesTakeTheSideOfTheCut) {
    const CutBlockSpec spec;
    for (bool snap : {false, true}) {
        World w = cut_block_world(spec, 8);
        w.snap.enabled = snap;
        ASSERT_GT(cut_with_polygon(w, cut_block_polygon(spec)), 0);
        const double e = 1e-6 * spec.size.x();
        const Vec3 lip(spec.cut_x, 0.5 * spec.size.y(), 0.75 * spec.size.z()), below(spec.cut_x, 0.5 * spec.size.y(), 0.25 * spec.size.z());
        const auto p = locate_points(w, {lip - Vec3(e, 0, 0), lip + Vec3(e, 0, 0), below - Vec3(e, 0, 0), below + Vec3(e, 0, 0)});
        pull_block_ends(w, spec);
        ASSERT_TRUE(solve_equilibrium(w).converged) << (snap ? "snap" : "xfem");
        const double open_lip = probe_displacement(w, p[1]).x() - probe_displacement(w, p[0]).x();
        const double open_below = probe_displacement(w, p[3]).x() - probe_displacement(w, p[2]).x();
        EXPECT_GT(open_lip, 0.1 * spec.pull) << (snap ? "snap" : "xfem") << ": the lips separate";
        EXPECT_LT(std::abs(open_below), 1e-4 * spec.pull) << (snap ? "snap" : "xfem") << ": below the front the body is whole";
    }
}

TEST(AccuracyBench, BadOptionsAreRejected) {
    AccuracyBenchOptions o = AccuracyBenchOptions::tiny();
    o.problems = {4};
    EXPECT_THROW(run_accuracy_bench(o), std::invalid_argument);
    o = AccuracyBenchOptions::tiny();
    o.block_levels = {6};  // 3 cells through the height: the crack front misses the grid planes
    EXPECT_THROW(run_accuracy_bench(o), std::invalid_argument);
    o = AccuracyBenchOptions::tiny();
    o.plate_levels = {5};
    EXPECT_THROW(run_accuracy_bench(o), std::invalid_argument);
    o = AccuracyBenchOptions::tiny();
    o.block_reference = 8;
    EXPECT_THROW(run_accuracy_bench(o), std::invalid_argument);
}

}  // namespace
}  // namespace xcut
