// `xcut bench --suite locking` (tools/bench/bench_locking.h): its tiny run scores both elements
// against CalculiX at nu 0 and 0.49 on the beam and at 0.49 on Cook's membrane, both cutters on the
// cut block (problem 5) at nu 0.3 and 0.49 (and XFEM on quadratic tetrahedra), and its verdicts say
// what the record says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include <cstdlib>
#include <map>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "tools/bench/bench_accuracy.h"
#include "tools/bench/bench_locking.h"
#include "tools/studies/calculix_reference.h"

namespace xcut {
namespace {

TEST(LockingBench, TinyRunScoresBothElementsAgainstCalculix) {
    if (std::system("command -v ccx > /dev/null 2>&1") != 0) GTEST_SKIP() << "no CalculiX (calculix-ccx)";
    LockingBenchOptions o;
    o.tiny = true;
    o.cache_dir = std::string(XCUT_BUILD_DIR) + "/accuracy_cache";
    std::vector<std::string> notes;
    const std::vector<LockingBenchRow> rows = run_locking_bench(o, &notes);
    // The quadratic snapping cutter's row at nu 0.3 (9.05 %) lies at the edge of this run's scoring
    // rule (10 x the reference's own 0.9 %): whether it is scored is not what this test checks.
    const auto scored = std::count_if(rows.begin(), rows.end(), [](const LockingBenchRow& r) { return r.element != "snap-quadratic"; });
    ASSERT_EQ(scored, 24) << "the beam: two ratios, three elements (linear, quadratic, quadratic-p0), two "
                                   "levels; Cook's membrane: nu 0.49; "
                                   "the block: two ratios, two cutters, two levels; notes:\n"
                                << fmt::format("{}", fmt::join(notes, "\n"));
    double cook_linear = 0.0, cook_quadratic = 0.0;
    std::map<std::tuple<std::string, double, int>, double> block;  // (cutter, nu, n) -> error
    for (const LockingBenchRow& r : rows) {
        if (r.problem == "block") {
            EXPECT_NE(r.reference_source.find("CalculiX C3D20"), std::string::npos);
            EXPECT_GT(r.error, 0.0);
            if (r.element != "snap-quadratic") block[{r.element, r.poisson, r.n}] = r.error;
            continue;
        }
        if (r.problem == "cook") {  // plane strain at nu 0.49, 4 x 4 cells: both lock, the linear one far more
            EXPECT_NE(r.reference_source.find("CalculiX CPE8R"), std::string::npos);
            if (r.n == 4) (r.element == "linear" ? cook_linear : cook_quadratic) = r.error;
            continue;
        }
        SCOPED_TRACE(r.element + " nu " + std::to_string(r.poisson) + " n " + std::to_string(r.n));
        EXPECT_NE(r.reference_source.find("CalculiX"), std::string::npos);
        if (r.element == "linear") {
            EXPECT_LT(r.error, -0.4) << "the linear element locks on 1-2 cells through the beam";
        } else {
            EXPECT_TRUE(r.poisson != 0.0 || std::abs(r.error) < 0.005) << r.error;
            // the 10k-DOF target; the constant pressure bends too softly (+2.5 % at nu 0.49 in the full
            // suite, +4 % against this run's coarser reference: docs/elements.md)
            EXPECT_TRUE(r.n != 2 || std::abs(r.error) < (r.element == "quadratic" ? 0.02 : 0.05)) << r.error;
        }
        EXPECT_LE(r.dofs, 10000);
    }
    EXPECT_LT(cook_linear, -0.5);
    EXPECT_LT(std::abs(cook_quadratic), 0.5 * std::abs(cook_linear)) << cook_quadratic << " against " << cook_linear;
    // Cut tissue keeps the linear element: at nu 0.49 both cutters lock alike, their error at 8 cells
    // about twice that at 0.3 (measured 17.0 / 34.9 % XFEM, 17.9 / 34.8 % snapping), and it falls
    // more slowly with refinement (4 -> 8 cells: 30 -> 17 % at 0.3, 45 -> 35 % at 0.49).
    ASSERT_EQ(block.size(), 8u);
    for (const char* cutter : {"xfem", "snap"}) {
        SCOPED_TRACE(cutter);
        const double soft4 = block[{cutter, 0.3, 4}], soft8 = block[{cutter, 0.3, 8}];
        const double hard4 = block[{cutter, 0.49, 4}], hard8 = block[{cutter, 0.49, 8}];
        EXPECT_GT(hard8, 1.5 * soft8);
        EXPECT_LT(soft8, 0.7 * soft4);
        EXPECT_GT(hard8, 0.7 * hard4);
    }
    const double xfem = block[{"xfem", 0.49, 8}], snap = block[{"snap", 0.49, 8}];
    EXPECT_NEAR(xfem, snap, 0.05) << "the cutters lock alike";
    // XFEM on quadratic tetrahedra (docs/elements.md) at 4 cells against the linear element at 8 (459
    // DOFs against 294): measured 8.3 % at nu 0.3 and 13 % at 0.49 against the linear XFEM's 16.9 %
    // and 34.8 %. The tiny run's references (own error 0.9 and 1.4 %) are too coarse to score them
    // (the suite says so), so they are compared here against the same references, the margins far
    // above those errors.
    for (const double nu : {0.3, 0.49}) {
        SCOPED_TRACE(nu);
        bool said = false;
        for (const std::string& n : notes)
            said = said || (n.find(fmt::format("block nu {} xfem-quadratic n 4: NOT scored", nu)) != std::string::npos);
        EXPECT_TRUE(said) << "the suite says why it did not score the quadratic run";
        CutBlockSpec spec;
        spec.poisson = nu;
        spec.reference_grading = 1.0;  // the locking suite's reference (tools/bench/bench_locking_cut.cpp)
        const ExternalReference ref = calculix_reference(5, cut_block_parameters(spec), {8, 16, 32}, o.cache_dir);
        ASSERT_TRUE(ref.available) << ref.why;
        const double quadratic = cut_block_run(spec, 4, "xfem-quadratic", reference_points(ref)).error;
        const double linear = block[{"xfem", nu, 8}];
        EXPECT_LT(quadratic, (nu < 0.4 ? 0.7 : 0.5) * linear);
        // The snapping cutter on the same quadratic tetrahedra: as far below the linear snapping's
        // error, and within 10 % of the quadratic XFEM's (measured 9.05 against 8.33 % at nu 0.3,
        // 13.7 against 12.9 % at 0.49; on linear tetrahedra at 8 cells 17.9 against 17.0 %).
        const double snap_quadratic = cut_block_run(spec, 4, "snap-quadratic", reference_points(ref)).error;
        const double snap_linear = block[{"snap", nu, 8}];
        EXPECT_LT(snap_quadratic, (nu < 0.4 ? 0.7 : 0.5) * snap_linear);
        EXPECT_NEAR(snap_quadratic, quadratic, 0.1 * quadratic);
        // With a constant pressure per element (quadratic-p0): at nu 0.49 the full suite measured
        // 8.0 % against 12.9 % at 4 cells; here against the coarser reference, the margin above its error.
        const double constant_pressure = cut_block_run(spec, 4, "xfem-quadratic-p0", reference_points(ref)).error;
        std::printf("block nu %.2f, 4 cells: quadratic %.3g %%, with a constant pressure %.3g %%, snapped %.3g %%\n", nu,
                    100 * quadratic, 100 * constant_pressure, 100 * snap_quadratic);
        if (nu > 0.4) {
            EXPECT_LT(constant_pressure, 0.85 * quadratic);
        }
    }
    bool met = false;
    for (const std::string& line : locking_summary(rows))
        met = met || (line.find("beam nu 0.49 quadratic") != std::string::npos && line.find("target met") != std::string::npos);
    EXPECT_TRUE(met);
}

}  // namespace
}  // namespace xcut
