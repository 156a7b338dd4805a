// `xcut bench --suite locking` (tools/bench/bench_locking.h): its tiny run scores both elements
// against CalculiX at nu 0 and 0.49 on the beam and at 0.49 on Cook's membrane, and its verdicts say
// what the record says.
#include <gtest/gtest.h>

#include <cstdlib>

#include "tools/bench/bench_locking.h"

namespace xcut {
namespace {

TEST(LockingBench, TinyRunScoresBothElementsAgainstCalculix) {
    if (std::system("command -v ccx > /dev/null 2>&1") != 0) GTEST_SKIP() << "no CalculiX (calculix-ccx)";
    LockingBenchOptions o;
    o.tiny = true;
    o.cache_dir = std::string(XCUT_BUILD_DIR) + "/accuracy_cache";
    std::vector<std::string> notes;
    const std::vector<LockingBenchRow> rows = run_locking_bench(o, &notes);
    ASSERT_EQ(rows.size(), 12u) << "the beam: two ratios, two elements, two levels; Cook's membrane: nu 0.49";
    double cook_linear = 0.0, cook_quadratic = 0.0;
    for (const LockingBenchRow& r : rows) {
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
            EXPECT_TRUE(r.n != 2 || std::abs(r.error) < 0.02) << "the 10k-DOF target: " << r.error;
        }
        EXPECT_LE(r.dofs, 10000);
    }
    EXPECT_LT(cook_linear, -0.5);
    EXPECT_LT(std::abs(cook_quadratic), 0.5 * std::abs(cook_linear)) << cook_quadratic << " against " << cook_linear;
    bool met = false;
    for (const std::string& line : locking_summary(rows))
        met = met || (line.find("beam nu 0.49 quadratic") != std::string::npos && line.find("target met") != std::string::npos);
    EXPECT_TRUE(met);
}

}  // namespace
}  // namespace xcut
