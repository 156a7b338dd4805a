// docs/verification.md problem 7 (slivers) for XFEM: cuts at distance delta * h from a node layer,
// delta = 1e-1 ... 1e-9, and cuts exactly through a face, an edge and a node. A clamped block is cut
// through and stepped under gravity with implicit Euler.
// Bounds stated here: CG reaches 1e-8 relative residual within kCgBound iterations every step; no
// NaN; kinetic + elastic energy never exceeds the work gravity did (implicit Euler only dissipates).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/test_helpers.h"

namespace xcut {
namespace {

using testing::cut_now;
using testing::grid;
using testing::square_on_plane;
using testing::step_world;

constexpr int kCgBound = 150;  // measured: at most 89 over all cases below
constexpr double kH = 0.005;  // element size [m]

struct SliverCase {
    const char* name;
    Vec3 point;    ///< on the cut plane [m]
    Vec3 normal;
};

World clamped_block() {
    Material m;  // the paper's skin: E = 1e4 Pa, nu = 0.3, rho = 1000 kg/m^3
    World w;
    w.materials.list = {m};
    w.constraints.boxes.push_back({Vec3(-1, -1, -1), Vec3(1e-9, 1, 1), 7});
    build_bodies(w, generate_box(grid({0.02, 0.01, 0.01}, {4, 2, 2})));
    w.gravity = Vec3(0, 0, -9.81);
    w.solver.dt = 0.01;
    w.solver.cg_tolerance = 1e-8;
    w.solver.cg_max_iterations = 10 * kCgBound;  // let it run past the bound so a miss is seen
    return w;
}

void run_case(const SliverCase& c) {
    SCOPED_TRACE(c.name);
    World w = clamped_block();
    const int split = cut_now(w, square_on_plane(c.point, c.normal, 1.0));
    EXPECT_GT(split, 0);
    int max_cg = 0;
    for (int n = 0; n < 50; ++n) {
        step_world(w);
        const StepMetrics& m = w.metrics.current;
        max_cg = std::max(max_cg, m.cg_iterations);
        for (const Vec3& x : w.nodes.position) ASSERT_TRUE(x.allFinite()) << "step " << n;
        EXPECT_LE(m.kinetic_energy + m.elastic_energy, m.gravity_work * (1 + 1e-9) + 1e-15) << "step " << n;
    }
    EXPECT_LE(max_cg, kCgBound);
    // Bounded: nothing moves further than implicit Euler's free fall over the run, 1/2 g h^2 n (n + 1)
    // with n = 50, h = 0.01 s, plus 1 cm.
    double max_disp = 0.0;
    for (int i = 0; i < w.nodes.count(); ++i) max_disp = std::max(max_disp, (w.nodes.position[i] - w.nodes.rest[i]).norm());
    EXPECT_LT(max_disp, 0.5 * 9.81 * 1e-4 * 50 * 51 + 0.01);
    ::testing::Test::RecordProperty(std::string(c.name) + "_max_cg", max_cg);
    std::printf("  %-14s split %3d  max CG iterations %d  max displacement %.3g m\n", c.name, split, max_cg, max_disp);
}

TEST(XfemSlivers, NearNodeLayer) {
    for (double delta = 1e-1; delta >= 0.99e-9; delta /= 10.0) {
        char name[32];
        std::snprintf(name, sizeof name, "delta=%.0e", delta);
        run_case({name, Vec3(0.01 + delta * kH, 0.005, 0.005), Vec3(1, 0, 0)});
    }
}

TEST(XfemSlivers, ExactlyThroughFaces) { run_case({"face", Vec3(0.01, 0.005, 0.005), Vec3(1, 0, 0)}); }
TEST(XfemSlivers, ExactlyThroughAnEdge) { run_case({"edge", Vec3(0.01, 0.0, 0.0), Vec3(1, 0, 0.3)}); }
TEST(XfemSlivers, ExactlyThroughANode) { run_case({"node", Vec3(0.01, 0.005, 0.005), Vec3(1, 0.3, 0.2)}); }

}  // namespace
}  // namespace xcut
