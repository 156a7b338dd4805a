// What the programs that run the engine set before the runtimes load (engine/startup_environment.h),
// and Eigen leaving the threads to the systems (CMakeLists.txt, EIGEN_DONT_PARALLELIZE).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cstdlib>
#include <string>

#include "engine/parallel.h"

namespace xcut {
namespace {

// The test programs started again with OpenMP's passive wait policy (tests/test_main.cpp), unless
// whoever ran them chose one: a wait policy is set in this process either way.
TEST(StartupEnvironment, TheTestProgramRunsWithAWaitPolicy) {
    const char* policy = std::getenv("OMP_WAIT_POLICY");
    ASSERT_NE(policy, nullptr) << "ensure_startup_environment did not set OMP_WAIT_POLICY";
    EXPECT_FALSE(std::string(policy).empty());
}

// Eigen, compiled with OpenMP, would split a dense product over all of OpenMP's threads in a region
// of its own; the core is built so that it never does, whatever the systems' thread count.
TEST(StartupEnvironment, EigenUsesOneThreadWhateverTheSystemsCount) {
    set_thread_count(2);
    EXPECT_EQ(Eigen::nbThreads(), 1);
    Eigen::MatrixXd a = Eigen::MatrixXd::Random(96, 96), b = Eigen::MatrixXd::Random(96, 96);
    const Eigen::MatrixXd two = a * b;  // above Eigen's 50,000-flop threshold for splitting
    set_thread_count(1);
    const Eigen::MatrixXd one = a * b;
    EXPECT_EQ((two - one).cwiseAbs().maxCoeff(), 0.0) << "the same bits on 1 and 2 threads";
    set_thread_count(2);
}

}  // namespace
}  // namespace xcut
