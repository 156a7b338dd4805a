// `xcut stress` in CI's configuration (docs/verification.md problems 7-9, 100 random trajectories):
// every invariant is asserted. The paper's once-linearized implicit Euler gains energy on a slab
// twisted 180 degrees at dt >= 0.01 s; its rows are held to the watchdog's factor and their ratio
// printed, and with Newton iterations to convergence the step is asserted not to gain energy.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>

#include "components/cut_elements.h"
#include "engine/io/scene_checks.h"
#include "systems/pipeline.h"
#include "systems/surface/surface_cut.h"
#include "tools/studies/stress.h"
#include "tests/node_copies_check.h"
#include "tests/surface_checks.h"
#include "tests/test_helpers.h"

namespace xcut {
namespace {

/// CI's stress run: 100 trajectories of `seed` on the `front` (`blades` > 1: 2 to that many
/// scalpels each; `tip`: the 2D patch with crack tips), every invariant asserted.
/// `energy_known`: trajectories known to pass the energy bound (named where the test is called).
/// `count` and `element`: fewer trajectories, on tissue of that element.
void hundred_trajectories(unsigned seed, const std::string& front, int blades = 1, bool tip = false,
                          int energy_known = 0, int count = 100, const std::string& element = "linear") {
    StressOptions o;
    o.blades = blades;
    o.tip = tip;
    o.element = element;
    o.count = count;
    o.budget_s = 1e9;  // all 100, however slow the machine
    o.seed = seed;
    o.front = front;
    o.progress = false;
    o.csv = (std::filesystem::temp_directory_path() / ("xcut_stress_" + std::to_string(::getpid()) + ".csv")).string();
    o.csv_given = true;
    const auto summary = run_stress(o);
    const StressSummary& all = summary.at("all");
    EXPECT_EQ(all.cases, 12 + 8 + 8 + 8 + count) << "12 sliver cases, 8 large-step cases three times, the trajectories";
    EXPECT_EQ(all.nan, 0);
    EXPECT_EQ(all.cg_over, 0) << "max CG " << all.max_cg;
    EXPECT_EQ(all.lost_vertices, 0) << "every surface vertex on a live element";
    EXPECT_EQ(all.open_edges, 0) << "no gap in the surfaces";
    EXPECT_EQ(all.pinched_edges, 0) << "every surface a 2-manifold: each edge in two triangles";
    EXPECT_EQ(all.zero_area, 0) << "no triangle without area";
    const std::string problem = tip ? "8 crack tips" : blades > 1 ? "8 many blades" : "8 many cuts";
    EXPECT_EQ(summary.at(element == "linear" ? problem : problem + ", " + element).cases, count);
    // Backward Euler solved to convergence does not gain energy, at any dt up to 0.1 s.
    EXPECT_EQ(summary.at("9 large steps, Newton").energy_over, 0)
        << "max energy / work " << summary.at("9 large steps, Newton").max_energy_ratio;
    // Nor does the default step: once linearized, with Newton iterations where it gained energy.
    EXPECT_EQ(summary.at("9 large steps, checked").energy_over, 0)
        << "max energy / work " << summary.at("9 large steps, checked").max_energy_ratio;
    EXPECT_GT(summary.at("9 large steps").max_energy_ratio, 1.5) << "without the check the once-linearized step gains";
    EXPECT_EQ(all.energy_over, energy_known) << "max energy / work " << all.max_energy_ratio;
    EXPECT_EQ(all.violations(), energy_known);
    std::printf("  measured: once-linearized max energy / work %.3f (held to the watchdog's factor)\n",
                summary.at("9 large steps").max_energy_ratio);
    std::ifstream csv(o.csv);
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header,
              "problem,case,steps,cuts,max_cg,nan,energy_ratio,energy_bound,lost_vertices,open_edges,pinched_edges,"
              "zero_area_triangles,crossed_through,bridged,left_out,pieces,expected_pieces,strips,pieces_mismatch,"
              "piece_offset_mm,loop_gap_mm,tip_steps,slit_steps");
    int rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    EXPECT_EQ(rows, all.cases);
}

TEST(Stress, HundredTrajectoriesKeepEveryInvariant) { hundred_trajectories(7, "semi"); }

// The progressive front on other trajectories (seed 8): tip elements split on entry and opened edge
// by edge keep the surfaces closed, 2-manifold and without zero-area triangles.
TEST(Stress, HundredProgressiveTrajectoriesKeepEveryInvariant) { hundred_trajectories(8, "progressive"); }

// Quadratic tissue cut (docs/elements.md, "Cutting quadratic elements"), on both fronts and with
// several blades (seeds 12-14, 20 trajectories each): every invariant as for the linear element.
// Three tests, so that ctest runs them side by side (each takes about as long as a hundred linear
// trajectories).
TEST(Stress, QuadraticTrajectoriesKeepEveryInvariant) { hundred_trajectories(12, "semi", 1, false, 0, 20, "quadratic"); }
TEST(Stress, QuadraticProgressiveTrajectoriesKeepEveryInvariant) {
    hundred_trajectories(13, "progressive", 1, false, 0, 20, "quadratic");
}
TEST(Stress, QuadraticMultiBladeTrajectoriesKeepEveryInvariant) {
    hundred_trajectories(14, "semi", 4, false, 0, 20, "quadratic");
}

// Several scalpels at once (seed 9, 2-4 each): crossing one another's path in one step, through mesh
// nodes along grid planes, stabbing with a face; the surfaces stay closed, 2-manifold, without
// zero-area triangles, on both fronts.
TEST(Stress, HundredMultiBladeTrajectoriesKeepEveryInvariant) {
    hundred_trajectories(9, "semi", 4);
    hundred_trajectories(10, "progressive", 4);
}

// Several scalpels cutting one another's wounds again in 3D ("cutter.recut": true; seed 1, the first
// 26 of `xcut stress --blades 4 --recut`): no NaN, CG within its bound, energy within the work put
// in, every surface vertex on a live element, no triangle without area (trajectories 0, 3, 18 and
// 25 had some before a snapped point on its neighbours' line made its polygon fan from the centre).
// Open and pinched edges are not held yet (docs/xfem.md, Scalpels in 3D): they are printed.
TEST(Stress, ScalpelsCuttingAgainIn3dKeepTheSolverAndTheSurfacesVertices) {
    StressOptions o;
    const int count = testing::kInstrumented ? 8 : 26;  // the sanitizer build: trajectories 0 and 3
    o.blades = 4, o.recut = true, o.count = count, o.budget_s = 1e9, o.seed = 1, o.progress = false;
    o.csv = (std::filesystem::temp_directory_path() / ("xcut_stress_recut_" + std::to_string(::getpid()) + ".csv")).string();
    o.csv_given = true;
    const StressSummary r = run_stress(o).at("8 many blades, cut again");
    EXPECT_EQ(r.cases, count);
    EXPECT_EQ(r.nan, 0);
    EXPECT_EQ(r.cg_over, 0) << "max CG " << r.max_cg;
    EXPECT_EQ(r.energy_over, 0) << "max energy / work " << r.max_energy_ratio;
    EXPECT_EQ(r.lost_vertices, 0) << "every surface vertex on a live element";
    EXPECT_EQ(r.zero_area, 0) << "no triangle without area";
    EXPECT_EQ(r.pinched_edges, 0) << "wounds touching along a trace are split (surface_manifold.h)";
    std::printf("  measured: open edges %d over %d trajectories\n", r.open_edges, r.cases);
}

/// Each of these trajectories of `xcut stress --blades 4 --recut` (seed 1, numbered as the first 1,000
/// number them) runs with a closed, 2-manifold surface, every vertex on a live element and no
/// triangle without area.
void expect_closed_and_manifold(const std::vector<int>& trajectories) {
    for (const int n : trajectories) {
        StressOptions o;
        o.blades = 4, o.recut = true, o.count = 1000, o.only = n, o.budget_s = 1e9, o.seed = 1, o.progress = false;
        o.csv = (std::filesystem::temp_directory_path() / ("xcut_stress_traced_" + std::to_string(::getpid()) + ".csv")).string();
        o.csv_given = true;
        const StressSummary r = run_stress(o).at("8 many blades, cut again");
        EXPECT_EQ(r.cases, 1) << "trajectory " << n;
        EXPECT_EQ(r.open_edges, 0) << "trajectory " << n;
        EXPECT_EQ(r.pinched_edges, 0) << "trajectory " << n;
        EXPECT_EQ(r.lost_vertices, 0) << "trajectory " << n;
        EXPECT_EQ(r.zero_area, 0) << "trajectory " << n;
    }
}

// Trajectories of `xcut stress --blades 4 --recut` (seed 1) whose open or pinched surface edges were
// each traced to one rule for several incisions at one place (docs/xfem.md, Scalpels in 3D): now
// closed and manifold. 86: a fragment's face across a plane whose fragment there is bounded by
// fewer planes (a double sheet); 87: two incisions crossing one skin edge, the whole element beside
// showing one; 3: a skin subdivision point snapped onto a crossing; 89: a plane's crossing of an
// edge where the plane meets it, not its recorded point; 77: a fragment touching the whole element
// across a face inside it, freed; 46: a further plane's own point on an edge missing from the
// crossings a polygon's point snaps to; 42: two traces crossing on a face, each element's own
// point (48 open edges without snap_to_traces); 38: the same where the element across has one of
// the traces only; 22: two traces ending at one point of an edge (their planes cross a hair off
// it); 24: a neighbour's further plane crossing a cut-once element's rim where its recorded trace
// does not; 49: a point near two traces at 30 degrees, beyond `within` of their crossing (closed;
// its two pinched edges: two wounds touching along a trace, below); 556 and 907 (of the first
// 1,000): a polygon fanned from its first point with a flat triangle between points not next to
// each other (a triangle without area each).
TEST(Stress, TracedRecutTrajectoriesAreClosedAndManifold) {
    expect_closed_and_manifold({86, 87, 3, 89, 77, 46, 42, 38, 22, 24, 49, 556, 907});
}

// Trajectories (seed 1) whose surfaces were closed but pinched where wounds touch
// (systems/surface/surface_manifold.h): 2, lips joined along the trace of an incision on the skin
// (the lens closes onto the skin: skin and wound in one edge) and two cut-once elements' lenses
// touching on the face between them; 4 and 12, a cut-once element's lens and an element cut
// again touching so; 64, a wound whose two lips are made of the same vertices (two triangles on the
// same corners, one each way); 55, a piece of skin made twice, one each way; 228, two lenses
// whose own pairs stay joined round both ends of the edge (paired the other way: one wound through
// the face). Before the split they held 10, 2, 4, 18, 1 and 2 pinched edges (with no open one):
// now none, and the steps are the same (the copies move with their vertices; contacts and grasps
// act on the vertex itself).
TEST(Stress, WoundsTouchingAlongATraceKeepTheSurfaceManifold) { expect_closed_and_manifold({2, 4, 12, 64, 55, 228}); }

// Crack tips at the blade (2D patch, seed 11; tips within 0, 2 and 4 mm, blades that enter, leave,
// cross their own path and stand): no NaN, CG within its bound, the sheet's vertices on live
// elements, no overlapping or zero-area triangles, no energy gained. Trajectory 18 gained 1.148 x the
// work with the paper's once-linearized step alone (its gain at large rotations, as in problem 9);
// the step's energy check now goes on with Newton iterations where a step gains
// (systems/solver/energy_check.h), and Newton iterations to convergence at every step hold the bound too.
TEST(Stress, HundredCrackTipTrajectoriesKeepEveryInvariant) {
    hundred_trajectories(11, "semi", 1, true, 0);
    StressOptions newton;
    newton.tip = true, newton.seed = 11, newton.only = 18, newton.newton = 20, newton.progress = false;
    const std::string name = "xcut_newton_" + std::to_string(::getpid()) + ".csv";
    newton.csv = (std::filesystem::temp_directory_path() / name).string();
    newton.csv_given = true;
    const StressSummary tips = run_stress(newton).at("8 crack tips");
    EXPECT_EQ(tips.cases, 1);
    EXPECT_EQ(tips.energy_over, 0) << "max energy / work " << tips.max_energy_ratio;
    EXPECT_LT(tips.max_energy_ratio, 0.9);
    std::mt19937_64 rng(11);
    std::set<double> radii;
    int standing = 0, outside = 0;
    for (int n = 0; n < 100; ++n) {
        const Scene s = random_tip_scene(rng);
        radii.insert(s.tip_radius);
        const auto& k = s.tools.trajectory[0];
        standing += (k[2].position - k[1].position).norm() < 2e-4;
        for (const Keyframe& key : k)
            outside += key.position.head<2>().minCoeff() < 0.0 || key.position.head<2>().maxCoeff() > 0.04;
    }
    EXPECT_EQ(radii, (std::set<double>{0.0, 0.002, 0.004}));
    EXPECT_GT(standing, 10);
    EXPECT_GT(outside, 10);
}

// Crack fronts at the blades (3D slab, seed 1; fronts within 0, 2 and 4 mm, the blades deeper than
// the slab carrying one): the first 24 trajectories and trajectory 185, whose blade kept a front
// while it stood and the split then caught up with it (the front's line ran through no uncut
// element any more, and its zone could not be built: the run stopped); the front is now handed to
// where the edge is. Every invariant held over the first 1,000 (docs/BENCHMARKS.md).
TEST(Stress, CrackFrontTrajectoriesKeepEveryInvariant) {
    for (int only : {-1, 185}) {
        StressOptions o;
        o.fronts = true, o.seed = 1, o.count = 24, o.only = only, o.budget_s = 1e9, o.progress = false;
        o.csv = (std::filesystem::temp_directory_path() / ("xcut_fronts_" + std::to_string(::getpid()) + ".csv")).string();
        o.csv_given = true;
        const auto summary = run_stress(o);
        const StressSummary& fronts = summary.at("8 crack fronts");
        EXPECT_EQ(fronts.cases, only < 0 ? 24 : 1);
        EXPECT_EQ(fronts.violations(), 0) << "max CG " << fronts.max_cg << ", max energy / work " << fronts.max_energy_ratio;
        std::ifstream csv(o.csv);
        std::string line;
        int with_fronts = 0;
        while (std::getline(csv, line))
            if (line.rfind("\"8 crack fronts\"", 0) == 0) with_fronts += std::stoi(line.substr(line.rfind(',') + 1)) > 0;
        EXPECT_GT(with_fronts, 0) << "some blades cross the slab whole and carry a front";
        std::filesystem::remove(o.csv);
    }
}

// The multi-blade generator makes what it says: 2 to 4 blades, stabs straight down their vertical
// edge with a face, blades with and without a face, the second blade through the first's waypoint
// at the same instant, waypoints on a grid plane.
TEST(Stress, MultiBladeScenesHoldEveryKindOfBlade) {
    std::mt19937_64 rng(3);
    int stabs = 0, faces = 0, faceless = 0, crossing = 0, on_grid = 0;
    std::set<int> counts;
    for (int n = 0; n < 200; ++n) {
        const Scene s = random_blades_scene(rng, "semi", 4);
        const ToolBodies& tb = s.tools;
        counts.insert(tb.count());
        ASSERT_EQ(tb.blade_back.size(), static_cast<size_t>(tb.count()));
        for (int b = 0; b < tb.count(); ++b) {
            const auto& k = tb.trajectory[b];
            const bool stab = k[0].position.head<2>() == k[2].position.head<2>() && k[0].position.z() > k[2].position.z();
            stabs += stab;
            faces += tb.blade_back[b] != Vec3::Zero();
            faceless += tb.blade_back[b] == Vec3::Zero();
            EXPECT_TRUE(!stab || tb.blade_back[b] != Vec3::Zero()) << "a stab cuts with its face";
            if (b == 1) crossing += k[1].position == tb.trajectory[0][1].position;
            const auto grid = [](double v) { return std::abs(v / 0.004 - std::round(v / 0.004)) < 1e-12; };
            on_grid += !stab && ((grid(k[0].position.x()) && grid(k[1].position.x()) && grid(k[2].position.x())) ||
                                 (grid(k[0].position.y()) && grid(k[1].position.y()) && grid(k[2].position.y())));
        }
    }
    EXPECT_EQ(counts, (std::set<int>{2, 3, 4}));
    EXPECT_GT(stabs, 0);
    EXPECT_GT(faces, stabs) << "drawn blades with a face too";
    EXPECT_GT(faceless, 0);
    EXPECT_GT(crossing, 0);
    EXPECT_GT(on_grid, 0);
}

// A run short of the record's 10^4 trajectories writes <record>_quick.csv, never the record.
TEST(Stress, AShortRunNeverOverwritesTheRecord) {
    const auto dir = std::filesystem::temp_directory_path() / ("xcut_stress_record_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    StressOptions o;
    o.count = 1;
    o.progress = false;
    o.csv = (dir / "bench_stress.csv").string();
    run_stress(o);
    EXPECT_FALSE(std::filesystem::exists(dir / "bench_stress.csv"));
    EXPECT_TRUE(std::filesystem::exists(dir / "bench_stress_quick.csv"));
    std::filesystem::remove_all(dir);
}

// Seed 1's second trajectory splits elements whose nodes' H (from earlier splits) cross an edge the
// blade did not: that edge's point falls back to its midpoint, where the once-subdivided skin has a
// vertex. The surfaces used to get a second vertex there and stay open along the lips (12 edges).
/// Trajectory `index` of `seed` (problem 8), run to its end: every mesh edge the crack crosses has
/// one point, whichever cut element holds it, and the surfaces are closed and consistently oriented.
void expect_closed_after_trajectory(int index, unsigned seed = 1, const std::string& front = "semi") {
    std::mt19937_64 rng(seed);
    for (int i = 0; i < index; ++i) random_cut_scene(rng, front);
    auto sim = make_simulation(random_cut_scene(rng, front), false);
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
    EXPECT_EQ(zero_area_triangles(w.visual), 0);
    EXPECT_EQ(zero_area_triangles(w.collision), 0);
}

TEST(Stress, CutPointOnASkinSubdivisionVertexLeavesClosedSurfaces) { expect_closed_after_trajectory(1); }

// Trajectories that left gaps: 5, a skin vertex a nanometre beside a nudged edge point, sided by
// the plane; 56, the cut face's rim sorted by angle (a bow-tie of edge points around a fallback
// midpoint); 60, a skin crossing clamped to a skin vertex the plane through all edge points put on
// the wrong side. Each fails on the code before the fix.
class GapTrajectory : public ::testing::TestWithParam<int> {};
TEST_P(GapTrajectory, LeavesClosedSurfaces) { expect_closed_after_trajectory(GetParam()); }
INSTANTIATE_TEST_SUITE_P(Stress, GapTrajectory, ::testing::Values(5, 56, 60));

// Trajectories 19, 37 and 45 of seed 1: two crack sheets ending on one mesh edge, or the two lips
// of an element with both ends of an edge on the front, shared a surface edge with the lips of the
// next element (pinched: four triangles on one edge), and the seams at the front had no area.
INSTANTIATE_TEST_SUITE_P(Pinched, GapTrajectory, ::testing::Values(19, 37, 45));

// Trajectory 626 of seed 2: a mesh edge was crossed by a later blade pass at another point than the
// cut element already holding it (a fallback midpoint), so the crack had two points on one edge
// and the surface, one vertex per edge and side, a gap.
TEST(Stress, EachCrossedEdgeHasOneCrackPoint) { expect_closed_after_trajectory(626, 2); }

// Progressive-front trajectories of seed 1 that left pinched or open surface edges: a tip element's
// split, queued in the same step as a neighbour's that fixed one of its nodes on the other side of
// its plane, put the point of an uncrossed edge onto a node (its levels extrapolated, clamped to 0
// or 1). Such an edge now takes the midpoint, as on the semi-progressive front.
class ProgressiveTrajectory : public ::testing::TestWithParam<int> {};
TEST_P(ProgressiveTrajectory, LeavesClosedSurfaces) { expect_closed_after_trajectory(GetParam(), 1, "progressive"); }
INSTANTIATE_TEST_SUITE_P(Stress, ProgressiveTrajectory, ::testing::Values(6, 104, 159, 215));

// Trajectory 4824 of the multi-blade record (seed 1): a blade on a grid plane holding a top edge of
// the slab "crossed" the element under that edge within 1e-8 m of its top face, a cut face without
// area however triangulated (two zero-area triangles). A cut lying on a skin face makes no flap:
// the element stays whole, the end of the run says so, and the surfaces are closed, without
// zero-area triangles.
/// Trajectory `index` of the multi-blade record (seed 1, 2 to 4 blades), run to its end.
std::unique_ptr<Simulation> blades_trajectory(int index) {
    std::mt19937_64 rng(1);
    for (int i = 0; i < index; ++i) random_blades_scene(rng, "semi", 4);
    auto sim = make_simulation(random_blades_scene(rng, "semi", 4), false);
    for (int i = 0; i < kRandomCutSteps; ++i) step_simulation(*sim);
    return sim;
}

TEST(Stress, ABladeLyingOnTheSkinMakesNoFlap) {
    const auto sim = blades_trajectory(4824);
    const World& w = sim->world;
    int on_skin = 0;
    for (int n : w.cut_state.on_skin_ignored) on_skin += n;
    EXPECT_GT(on_skin, 0);
    EXPECT_GT(w.cuts.count(), 10) << "the incisions themselves are made";
    std::string notes;
    for (const std::string& n : end_of_run_notes(w)) notes += n + "\n";
    EXPECT_NE(notes.find("lay on the tissue's surface"), std::string::npos) << notes;
    testing::check_closed_oriented(w.visual);
    testing::check_closed_oriented(w.collision);
    EXPECT_EQ(zero_area_triangles(w.visual), 0);
    EXPECT_EQ(zero_area_triangles(w.collision), 0);
}

// Trajectory 3113 of the multi-blade record (seed 1): two incisions meet, and an element's cut runs
// through nodes whose sides the other incision fixed. The plane fitted through its points left one
// node on the wrong side, and its cut face, oriented by that plane, ran the wrong way round: eight
// open edges on each surface. Each side's cut face now faces away from its own nodes.
TEST(Stress, IncisionsMeetingOrientTheirCutFacesByTheNodesSides) {
    const auto sim = blades_trajectory(3113);
    const World& w = sim->world;
    EXPECT_GT(w.cuts.count(), 10);
    testing::check_closed_oriented(w.visual);
    testing::check_closed_oriented(w.collision);
    EXPECT_EQ(zero_area_triangles(w.visual), 0);
    EXPECT_EQ(zero_area_triangles(w.collision), 0);
}

// Several incisions meeting, on the multi-blade record's first trajectories (seed 1) and the two
// above: every node's copies are still the classes of material connectivity computed from scratch
// (the engine updates them only at the nodes of elements a step split or crossed). Before the copies
// were made by connectivity, 55 of the first 60 of these trajectories had nodes where the engine's
// rule (the real node on both sides of a second incision's element) and connectivity differed.
TEST(Stress, IncisionsMeetingKeepEachNodesCopiesByMaterialConnectivity) {
    int checked = 0;
    std::vector<int> trajectories(60);
    std::iota(trajectories.begin(), trajectories.end(), 0);
    trajectories.insert(trajectories.end(), {3113, 4824});
    for (int k : trajectories) {
        const auto sim = blades_trajectory(k);
        std::string first;
        EXPECT_EQ(testing::nodes_off_connectivity(sim->world, first), 0) << "trajectory " << k << ": " << first;
        checked += sim->world.enriched.count();
    }
    EXPECT_GT(checked, 1000) << "phantoms looked at";
}

/// The CSV row of `name` (a case) in the file at `path`, empty if none.
std::string csv_row(const std::string& path, const std::string& name) {
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);)
        if (line.find("\"" + name + "\"") != std::string::npos) return line;
    return {};
}

// `xcut stress --only K` runs the trajectory a full run of the same seed numbers K, alone: its row is
// the full run's row, field for field, and it never writes the record.
TEST(Stress, OnlyRunsTheTrajectoryAFullRunNumbersSo) {
    const auto dir = std::filesystem::temp_directory_path() / ("xcut_stress_only_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    StressOptions o;
    o.count = 3;
    o.blades = 4;
    o.seed = 5;
    o.progress = false;
    o.csv = (dir / "full.csv").string();
    o.csv_given = true;
    run_stress(o);
    o.only = 2;
    o.csv = (dir / "bench_stress.csv").string();
    o.csv_given = false;
    const StressSummary one = run_stress(o).at("all");
    EXPECT_EQ(one.cases, 1) << "that trajectory only";
    EXPECT_FALSE(std::filesystem::exists(dir / "bench_stress.csv"));
    const std::string full = csv_row((dir / "full.csv").string(), "trajectory 2");
    ASSERT_FALSE(full.empty());
    EXPECT_NE(full.find(",\"trajectory 2\",") , std::string::npos);
    EXPECT_EQ(csv_row((dir / "bench_stress_quick.csv").string(), "trajectory 2"), full);
    EXPECT_TRUE(csv_row((dir / "bench_stress_quick.csv").string(), "trajectory 1").empty());
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace xcut
