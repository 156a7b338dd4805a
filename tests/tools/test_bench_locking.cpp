// `xcut bench --suite locking` (tools/bench/bench_locking.h): its tiny run scores both elements
// against CalculiX at nu 0 and 0.49, and its verdicts say what the record says.
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
    ASSERT_EQ(rows.size(), 8u) << "two ratios, two elements, two levels";
    for (const LockingBenchRow& r : rows) {
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
    bool met = false;
    for (const std::string& line : locking_summary(rows))
        met = met || (line.find("nu 0.49 quadratic") != std::string::npos && line.find("target met") != std::string::npos);
    EXPECT_TRUE(met);
}

}  // namespace
}  // namespace xcut
