// `xcut stress --loops` (tools/studies/stress_loops.h): closed loops drawn round random ellipses in
// a 2D skin patch, a cross-cut through the lens in two of three, the pieces freed checked against
// the regions the paths enclose.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "engine/fragment_geometry.h"
#include "engine/world.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"
#include "tools/studies/stress.h"
#include "tools/studies/stress_loops.h"

namespace xcut {
namespace {

/// f(scene, regions, n) for the first `count` loop scenes of seed 1.
template <class F>
void each_loop_scene(int count, F&& f) {
    std::mt19937_64 rng(1);
    for (int n = 0; n < count; ++n) {
        LoopRegions r;
        const Scene s = random_loop_scene(rng, &r);
        f(s, r, n);
    }
}

// The regions the scene's generator states (closed forms: the ellipse's area, a chord's segments,
// at rest) are the areas of the polygons its scalpels draw on the stretched patch, less its
// stretch: the loop's 61 waypoints, divided by the cross-cut's line where there is one (within
// 0.3 %: a polygon of that many sides inside the ellipse). Every draw keeps the paths 5 mm inside
// the held borders.
TEST(StressLoops, TheRegionsAreThoseThePathsEnclose) {
    int crossed = 0;
    each_loop_scene(60, [&](const Scene& s, const LoopRegions& r, int) {
        const auto& loop = s.tools.trajectory[0];
        ASSERT_EQ(loop.size(), 62u);
        std::vector<Vec3> ring;  // the loop's first turn: 57 of its 61 steps of (2 pi + 0.4) / 60
        for (size_t k = 0; k < loop.size(); ++k) {
            if (k >= 1 && k <= 57) ring.push_back(loop[k].position);
            EXPECT_GT(loop[k].position.head<2>().minCoeff(), 0.005 - 1e-12);
            EXPECT_LT(loop[k].position.head<2>().maxCoeff(), 0.035 + 1e-12);
        }
        if (s.tools.count() == 1) {
            ASSERT_EQ(r.area.size(), 1u);
            EXPECT_NEAR(polygon_area(ring) / (kLoopStretch * kLoopStretch), r.area[0], 3e-3 * r.area[0]);
            return;
        }
        ++crossed;
        ASSERT_EQ(r.area.size(), 2u);
        const Vec3 from = s.tools.trajectory[1].front().position, to = s.tools.trajectory[1].back().position;
        const Vec3 m = (to - from).normalized();
        const CutLine chord{from, Vec3(-m.y(), m.x(), 0.0)};
        const double rest = 1.0 / (kLoopStretch * kLoopStretch);  // the drawn areas at rest
        const double left = rest * polygon_area(clip_to_side(ring, chord, true));
        const double right = rest * polygon_area(clip_to_side(ring, chord, false));
        EXPECT_NEAR(std::min(left, right), std::min(r.area[0], r.area[1]), 3e-3 * (r.area[0] + r.area[1]));
        EXPECT_NEAR(std::max(left, right), std::max(r.area[0], r.area[1]), 3e-3 * (r.area[0] + r.area[1]));
        EXPECT_GT(std::min(r.area[0], r.area[1]), 0.19 * (r.area[0] + r.area[1])) << "a chord at most half way to the rim";
    });
    EXPECT_GT(crossed, 25);
    EXPECT_LT(crossed, 55);
}

// A cross-cut after the loop is scored against the chord its blade cut through the lens's material
// (the freed lens drifts and turns): the regions a path divides the ellipse into are the closed
// forms' for the drawn chord (at rest), and the blade is pulled back to rest through the lens's
// motion exactly when that motion is a turn, a shift and a shrink.
TEST(StressLoops, ACrossCutAfterTheLoopIsFollowedThroughTheLensMaterial) {
    int after = 0;
    each_loop_scene(40, [&](const Scene& s, const LoopRegions& r, int n) {
        EXPECT_EQ(r.cross_after_loop, s.tools.count() == 2 && s.tools.trajectory[1].size() == 3) << n;
        if (s.tools.count() < 2) return;
        // The drawn chord at rest, in 30 steps from 3 mm before the rim to 3 mm past it.
        const Vec3 from = s.tools.trajectory[1].front().position, to = s.tools.trajectory[1].back().position;
        const Vec3 pull(kLoopPull, kLoopPull, 0.0);
        std::vector<Vec3> path;
        for (int k = 0; k <= 30; ++k) path.push_back((from + (to - from) * (k / 30.0) + pull) / kLoopStretch);
        LoopRegions cut;
        ASSERT_TRUE(path_regions(r, path, cut));
        ASSERT_EQ(cut.area.size(), 2u);
        const double whole = r.area[0] + r.area[1];
        EXPECT_NEAR(std::min(cut.area[0], cut.area[1]), std::min(r.area[0], r.area[1]), 1e-4 * whole) << n;
        EXPECT_NEAR(std::max(cut.area[0], cut.area[1]), std::max(r.area[0], r.area[1]), 1e-4 * whole) << n;
        EXPECT_NEAR(cut.perimeter[0] + cut.perimeter[1], r.perimeter[0] + r.perimeter[1], 1e-4 * (r.perimeter[0] + r.perimeter[1]));
        EXPECT_FALSE(path_regions(r, {path.front(), path.front()}, cut)) << "a path that never enters";
        if (!r.cross_after_loop || after++ > 0) return;

        // The lens turned by 0.15 rad, shifted and shrunk by 2.5 %: the blade's point comes back to
        // the rest point it lies over.
        auto sim = make_simulation(s, false);
        World& w = sim->world;
        const Eigen::Rotation2Dd turn(0.15);
        const Eigen::Vector2d shift(0.0011, -0.0007);
        const auto moved = [&](const Vec3& X) {
            const Eigen::Vector2d x = turn * ((X - r.centre).head<2>() * 0.975) + r.centre.head<2>() + shift;
            return Vec3(x.x(), x.y(), X.z());
        };
        for (int i = 0; i < w.mesh_nodes; ++i) w.nodes.position[i] = moved(w.nodes.rest[i]);
        const Vec3 X = r.centre + Vec3(0.002, -0.001, 0.0);
        w.tools.position[1] = moved(X);
        w.time = 2.5;
        std::vector<Vec3> tracked;
        track_cross_cut(w, r, tracked);
        ASSERT_EQ(tracked.size(), 1u);
        EXPECT_LT((tracked[0] - X).head<2>().norm(), 1e-12);
        w.time = 3.1;  // the cross-cut is over
        track_cross_cut(w, r, tracked);
        EXPECT_EQ(tracked.size(), 1u);
    });
    EXPECT_GT(after, 0);
}

/// The loop trajectories `o` asks for (seed 1; its CSV in a file of its own, removed): their summary.
StressSummary run_loops(StressOptions o) {
    o.loops = true;
    o.budget_s = 1e9;
    o.seed = 1;
    o.progress = false;
    o.csv = (std::filesystem::temp_directory_path() / ("xcut_stress_loops_" + std::to_string(::getpid()) + ".csv")).string();
    o.csv_given = true;
    const auto by = run_stress(o);
    std::filesystem::remove(o.csv);
    return by.at("8 closed loops");
}

// The first 24 loop trajectories of seed 1 (4 under the sanitizer): every invariant of the stress
// suite holds on them (no NaN, CG within its bound, energy within the tension put in, every vertex
// bound to a live element, no pinched edge or triangle without area), and the pieces of an element
// or more are the regions the paths enclose. Strips are printed (docs/BENCHMARKS.md has the
// 1,000-trajectory run). Before the sheet's points bound to a whole element were listed with it
// (note_bound, systems/surface/surface_cut_parts.h), 22 of these 24 left vertices bound to an
// element cut since (72 in all).
TEST(StressLoops, TheFirstLoopsFreeThePiecesTheirPathsEnclose) {
    StressOptions o;
    o.count = testing::kInstrumented ? 4 : 24;
    const StressSummary s = run_loops(o);
    EXPECT_EQ(s.cases, o.count);
    EXPECT_EQ(s.nan, 0);
    EXPECT_EQ(s.cg_over, 0);
    EXPECT_EQ(s.energy_over, 0) << "max (kinetic + elastic) / tension put in " << s.max_energy_ratio;
    EXPECT_GT(s.max_energy_ratio, 0.0);
    EXPECT_EQ(s.lost_vertices, 0);
    EXPECT_EQ(s.pinched_edges, 0);
    EXPECT_EQ(s.zero_area, 0);
    std::printf("  measured: pieces differ from the regions in %d of %d loops, %d strips\n", s.pieces_mismatch, s.cases,
                s.strips);
    EXPECT_EQ(s.pieces_mismatch, 0);
}

// Loop trajectories of seed 1 that once kept a piece joined to another (docs/xfem.md, Several cuts
// per element), each freed now: 177, whose pass 2.5 um beside a node left the corner of the element
// it crossed there (cut by the loop's other pass) whole, 6e-7 of it, below the sliver bound a
// further cut of a triangle then had; 30, whose loop dipped into an element the cross-cut had cut
// and left it through the edge it went in by, 0.46 of it away, at the cross-cut's point there;
// 125, whose loop stopped inside an element, 0.3 mm short of the cross-cut through it, at the end
// of a quad: no stretch was left to cut, and its stem was not made; 173, a loop alone that stopped
// 0.1 mm beside where its first pass left the element it stopped in, its stem ending short of that
// wound (the nearest point of the wound's line lay outside the element); 182, whose closing pass
// left an element through the edge its first pass and the cross-cut had both crossed, and was
// joined to the cross-cut's point there, the first one found, not to its first pass's 0.12 of the
// edge from its own; 195, whose loop stopped inside the element it began in, never cut: its first
// crossing out of it had been forgotten when the blade left it; 399 and 301, whose cross-cut
// missed an edge 0.1 mm from a node as it crossed an element cut before (the freed lens; the loop
// crossing the cross-cut's wound): the tissue slid past the start of its next quad, anchored in
// space in that element (it is carried by the fragment now: systems/cut/material_anchor.h); 275
// (a loop alone) and 845, whose closing pass, running beside its first pass, dipped into the sliver
// of an element between that pass and a mesh line and left it through the edge it went in by, more
// than a fifth of the edge away: the second crossing of that edge was taken for a trembling blade,
// and the element stayed joined across the dip (it is cut to where the blade turned now: note_dip);
// 448, whose loop met the cross-cut's wound at 20 degrees and went on beside it, crossing the next
// element's edge 0.15 of it from the wound's point there: that crossing was taken for a blade
// retracing the wound and dropped, and its crossing out, away from the wound, was the element's only
// one (it counts with that one now: BladeCut::near). 119 and 237 freed the right pieces all along:
// their cross-cuts, after the loop, went through the freed lens as it drifted 1-2 mm and turned
// 5-10 degrees, and against the chord drawn in space the halves were off by 0.67-0.70 mm per mm of
// their boundary; against the chord the blade cut through the lens's material, 0.10-0.11. 781,
// whose loop began beside the cross-cut's wound: the line of its first pass in that element, run
// across it, met the edge to the next element 0.6 um from where the closing pass crossed it, and the
// parts below and above the loop overlapped by that much (material now overlaps by a thousandth of
// the edge: kEdgeOverlap2d in systems/cut/node_copies.cpp).
TEST(StressLoops, LoopsPassingBesideANodeOrDippingIntoACutElementFreeTheirPieces) {
    for (const int index : {177, 30, 125, 173, 182, 195, 399, 301, 275, 845, 448, 119, 237, 781}) {
        StressOptions o;
        o.only = index;
        const StressSummary s = run_loops(o);
        ASSERT_EQ(s.cases, 1);
        EXPECT_EQ(s.lost_vertices + s.pinched_edges + s.zero_area + s.nan, 0) << "trajectory " << index;
        EXPECT_EQ(s.pieces_mismatch, 0) << "trajectory " << index << ": the pieces are not the regions its paths enclose";
    }
}

}  // namespace
}  // namespace xcut
