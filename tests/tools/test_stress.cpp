// `xcut stress` in a tiny configuration (docs/verification.md problems 7-9): the invariants that hold are asserted;
// the two that do not hold everywhere are measured and printed (see docs/BENCHMARKS.md, stress):
// energy growth of the paper's once-linearized implicit Euler on a slab twisted 180 degrees at
// dt >= 0.01 s (with Newton iterations to convergence it is asserted not to grow), and pinched
// (closed but not 2-manifold) surface edges after some random trajectories.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "components/cut_elements.h"
#include "systems/pipeline.h"
#include "tools/studies/stress.h"
#include "tests/surface_checks.h"

namespace xcut {
namespace {

TEST(Stress, TinySuiteKeepsItsInvariants) {
    StressOptions o;
    o.count = 6;
    o.seed = 7;
    o.progress = false;
    o.csv = (std::filesystem::temp_directory_path() / ("xcut_stress_" + std::to_string(::getpid()) + ".csv")).string();
    const auto summary = run_stress(o);
    const StressSummary& all = summary.at("all");
    EXPECT_EQ(all.cases, 12 + 8 + 8 + 6) << "12 sliver cases, 8 large-step cases twice, 6 trajectories";
    EXPECT_EQ(all.nan, 0);
    EXPECT_EQ(all.cg_over, 0) << "max CG " << all.max_cg;
    EXPECT_EQ(all.lost_vertices, 0) << "every surface vertex on a live element";
    EXPECT_EQ(summary.at("7 slivers").open_edges + summary.at("7 slivers").pinched_edges, 0)
        << "closed 2-manifolds after cuts through nodes, edges, faces";
    EXPECT_EQ(summary.at("8 many cuts").open_edges, 0) << "no gap in the surface after random trajectories";
    EXPECT_EQ(summary.at("7 slivers").energy_over, 0);
    // Backward Euler solved to convergence does not gain energy, at any dt up to 0.1 s.
    EXPECT_EQ(summary.at("9 large steps, Newton").energy_over, 0)
        << "max energy / work " << summary.at("9 large steps, Newton").max_energy_ratio;
    std::printf("  measured, not asserted: pinched edges after random trajectories %d; max energy / work %.3f\n",
                summary.at("8 many cuts").pinched_edges, summary.at("9 large steps").max_energy_ratio);
    std::ifstream csv(o.csv);
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header, "problem,case,steps,cuts,max_cg,nan,energy_ratio,lost_vertices,open_edges,pinched_edges");
    int rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    EXPECT_EQ(rows, all.cases);
}

// Seed 1's second trajectory splits elements whose nodes' H (from earlier splits) cross an edge the
// blade did not: that edge's point falls back to its midpoint, where the once-subdivided skin has a
// vertex. The surfaces used to get a second vertex there and stay open along the lips (12 edges).
/// Trajectory `index` of `seed` (problem 8), run to its end: every mesh edge the crack crosses has
/// one point, whichever cut element holds it, and the surfaces are closed and consistently oriented.
void expect_closed_after_trajectory(int index, unsigned seed = 1) {
    std::mt19937_64 rng(seed);
    for (int i = 0; i < index; ++i) random_cut_scene(rng);
    auto sim = make_simulation(random_cut_scene(rng), false);
    for (int i = 0; i < kRandomCutSteps; ++i) step_simulation(*sim);
    const World& w = sim->world;
    ASSERT_GT(w.cuts.count(), 10);
    std::map<std::pair<int, int>, Vec3> point_on_edge;
    int shared = 0;
    for (int c = 0; c < w.cuts.count(); ++c)
        for (int k = 0; k < 4 && w.cuts.point_edge[c][k] >= 0; ++k) {
            const int* ed = kTetEdges[w.cuts.point_edge[c][k]];
            const int a = w.elements.nodes[w.cuts.element[c]][ed[0]], b = w.elements.nodes[w.cuts.element[c]][ed[1]];
            const auto [it, fresh] = point_on_edge.emplace(std::make_pair(std::min(a, b), std::max(a, b)), w.cuts.points[c][k]);
            if (fresh) continue;
            ++shared;
            EXPECT_LT((it->second - w.cuts.points[c][k]).norm(), 1e-15) << "edge " << a << "-" << b << " cut " << c;
        }
    EXPECT_GT(shared, 0) << "cut elements share crossed edges";
    testing::check_closed_oriented(w.visual);
    testing::check_closed_oriented(w.collision);
}

TEST(Stress, CutPointOnASkinSubdivisionVertexLeavesClosedSurfaces) { expect_closed_after_trajectory(1); }

// Trajectories that left gaps: 5, a skin vertex a nanometre beside a nudged edge point, sided by
// the plane; 56, the cut face's rim sorted by angle (a bow-tie of edge points around a fallback
// midpoint); 60, a skin crossing clamped to a skin vertex the plane through all edge points put on
// the wrong side. Each fails on the code before the fix.
class GapTrajectory : public ::testing::TestWithParam<int> {};
TEST_P(GapTrajectory, LeavesClosedSurfaces) { expect_closed_after_trajectory(GetParam()); }
INSTANTIATE_TEST_SUITE_P(Stress, GapTrajectory, ::testing::Values(5, 56, 60));

// Trajectory 626 of seed 2: a mesh edge was crossed by a later blade pass at another point than the
// cut element already holding it (a fallback midpoint), so the crack had two points on one edge
// and the surface, one vertex per edge and side, a gap.
TEST(Stress, EachCrossedEdgeHasOneCrackPoint) { expect_closed_after_trajectory(626, 2); }

}  // namespace
}  // namespace xcut
