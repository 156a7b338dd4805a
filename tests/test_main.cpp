// The test programs' main: GoogleTest's, after the startup environment the xcut program sets for
// itself (engine/startup_environment.h). ctest runs one test per core; OpenMP threads spinning while
// they wait took the cores from the test beside them (two quadratic stress tests side by side: 55 s,
// 30 s with the passive policy).
#include <gtest/gtest.h>

#include "engine/startup_environment.h"

int main(int argc, char** argv) {
    xcut::ensure_startup_environment(argv);
    testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
