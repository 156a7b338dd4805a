// `xcut stress --loops` (tools/studies/stress_loops.h): closed loops drawn round random ellipses in
// a 2D skin patch, a cross-cut through the lens in two of three, the pieces freed checked against
// the regions the paths enclose.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "engine/fragment_geometry.h"
#include "engine/world.h"
#include "systems/pipeline.h"
#include "tests/test_helpers.h"
#include "tools/studies/stress.h"
#include "tools/studies/parted_regions.h"
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

/// Scene s's drawn path of tool i at rest (its keyframes: x = S X - pull).
std::vector<Vec3> drawn_at_rest(const Scene& s, int i) {
    std::vector<Vec3> path;
    for (const Keyframe& k : s.tools.trajectory[i]) path.push_back((k.position + Vec3(kLoopPull, kLoopPull, 0.0)) / kLoopStretch);
    return path;
}

// The raster the suite scores against parts the patch as the closed forms do: the drawn paths at
// rest give the patch and the ellipse's region or its two segments (besides slivers, smaller than
// an element, where the overshoot's chords cross the first turn's), within 0.3 % of the ellipse (a
// polygon of 61 sides inside it) and a cell along the boundary. Each region's boundary is its part
// of the paths (the cross-cut's ends outside bound nothing), with the slivers' sides along the
// overshoot's 0.4 rad (up to 23 % more here).
TEST(StressLoops, TheRasterPartsTheDrawnPathsAsTheClosedFormsDo) {
    const double element = 0.002 * 0.002 / 2.0;  // the patch's triangles [m^2]
    each_loop_scene(12, [&](const Scene& s, const LoopRegions& r, int n) {
        std::vector<std::vector<Vec3>> paths;
        for (int i = 0; i < s.tools.count(); ++i) paths.push_back(drawn_at_rest(s, i));
        const PartedRegions parted = parted_regions(paths, Vec3::Zero(), Vec3(kLoopPatch, kLoopPatch, 0.0), kLoopRaster);
        std::vector<std::pair<double, double>> got;
        for (size_t k = 0; k < parted.area.size(); ++k)
            if (parted.area[k] >= element) got.push_back({parted.area[k], parted.boundary[k]});
        ASSERT_EQ(got.size(), r.area.size() + 1) << n;
        std::sort(got.rbegin(), got.rend());
        double whole = 0.0, perimeter = 0.0;
        for (size_t k = 0; k < r.area.size(); ++k) whole += r.area[k], perimeter += r.perimeter[k];
        EXPECT_NEAR(got[0].first, kLoopPatch * kLoopPatch - whole, 3e-3 * whole + kLoopRaster * perimeter) << n;
        std::vector<std::pair<double, double>> want;
        for (size_t k = 0; k < r.area.size(); ++k) want.push_back({r.area[k], r.perimeter[k]});
        std::sort(want.rbegin(), want.rend());
        for (size_t k = 0; k < want.size(); ++k) {
            EXPECT_NEAR(got[k + 1].first, want[k].first, 3e-3 * whole + kLoopRaster * want[k].second) << n;
            EXPECT_GT(got[k + 1].second, 0.997 * want[k].second) << n;
            EXPECT_LT(got[k + 1].second, 1.3 * want[k].second) << n;
        }
        Vec3 from = Vec3::Zero(), to = Vec3::Zero();
        EXPECT_EQ(closest_return(paths[0], from, to), 0.0) << "the overshoot crosses the loop's start";
    });
}

// A loop that ends beside its start does not part the patch: one region, its gap measured; closed
// across that gap, two, the lens a circle's area within half a cell along its rim. A path whose end
// crosses its start comes back to it at distance 0, where it crosses.
TEST(StressLoops, ALoopThatEndsBesideItsStartFreesNothing) {
    const Vec3 c(0.02, 0.02, 0.0);
    const double radius = 0.008, gap = 3e-4;
    std::vector<Vec3> loop;
    for (int k = 0; k <= 200; ++k) {  // 2 pi + 0.4, the radius shrinking by `gap` over the last 0.4 rad
        const double th = (2.0 * M_PI + 0.4) * k / 200, in = th > 2.0 * M_PI ? gap : gap * th / (2.0 * M_PI);
        loop.push_back(c + (radius - in) * Vec3(std::cos(th), std::sin(th), 0.0));
    }
    Vec3 from = Vec3::Zero(), to = Vec3::Zero();
    EXPECT_NEAR(closest_return(loop, from, to), gap, 2e-5);
    const Vec3 lo = Vec3::Zero(), hi(kLoopPatch, kLoopPatch, 0.0);
    EXPECT_EQ(parted_regions({loop}, lo, hi, kLoopRaster).area.size(), 1u);
    const PartedRegions closed = parted_regions({loop, {from, to}}, lo, hi, kLoopRaster);
    ASSERT_EQ(closed.area.size(), 2u);
    const double lens = std::min(closed.area[0], closed.area[1]);
    EXPECT_NEAR(lens, M_PI * radius * radius, 2.0 * M_PI * radius * (gap + kLoopRaster));
    const std::vector<Vec3> crossing{Vec3(0.5, 0, 0), Vec3(1, 0, 0), Vec3(4, 0, 0), Vec3(4, 4, 0), Vec3(0.7, 4, 0), Vec3(0.7, -1, 0)};
    EXPECT_EQ(closest_return(crossing, from, to), 0.0);
    EXPECT_LT((from - Vec3(0.7, 0, 0)).norm(), 1e-12);
}

// A blade is pulled back to rest through the tissue's current shape: with the patch turned by 0.15
// rad, shifted and shrunk by 2.5 %, its point comes back to the rest point it lies over; off the
// patch it adds nothing.
TEST(StressLoops, ABladeIsFollowedThroughTheMaterial) {
    std::mt19937_64 rng(1);
    Scene s = random_loop_scene(rng);
    while (s.tools.count() < 2) s = random_loop_scene(rng);
    auto sim = make_simulation(s, false);
    World& w = sim->world;
    const Vec3 c(0.02, 0.02, 0.0);
    const Eigen::Rotation2Dd turn(0.15);
    const Eigen::Vector2d shift(0.0011, -0.0007);
    const auto moved = [&](const Vec3& X) {
        const Eigen::Vector2d x = turn * ((X - c).head<2>() * 0.975) + c.head<2>() + shift;
        return Vec3(x.x(), x.y(), X.z());
    };
    for (int i = 0; i < w.nodes.count(); ++i) w.nodes.position[i] = moved(w.nodes.rest[i]);
    const Vec3 X = c + Vec3(0.002, -0.001, 0.0);
    w.tools.position[0] = moved(X);
    w.tools.position[1] = Vec3(-0.01, 0.02, 0.0);
    std::vector<std::vector<Vec3>> paths;
    track_blades(w, paths);
    ASSERT_EQ(paths.size(), 2u);
    ASSERT_EQ(paths[0].size(), 1u);
    EXPECT_LT((paths[0][0] - X).head<2>().norm(), 1e-12);
    EXPECT_TRUE(paths[1].empty());
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

/// Runs each loop trajectory (seed, index) alone: every invariant holds and its pieces are the
/// regions its paths enclose.
void expect_pieces_freed(const std::vector<std::pair<unsigned, int>>& runs) {
    for (const auto& [seed, index] : runs) {
        StressOptions o;
        o.seed = seed;
        o.only = index;
        const StressSummary s = run_loops(o);
        ASSERT_EQ(s.cases, 1);
        EXPECT_EQ(s.lost_vertices + s.pinched_edges + s.zero_area + s.nan, 0) << "seed " << seed << " trajectory " << index;
        EXPECT_EQ(s.pieces_mismatch, 0) << "seed " << seed << " trajectory " << index
                                        << ": the pieces are not the regions its paths enclose";
    }
}

// Loop trajectories of seed 2 (drawn after the mends above, none traced on it) that kept a piece
// joined, and seed 1's last, each freed now. 605, a loop alone: its closing pass ran 0.1 mm beside
// its first pass, dipped 0.1 mm into the corner of the element the first pass crossed past its
// start, went back out through the edge it came in by and stopped beyond it, by that pass's wound;
// the corner stayed one with the skin across the node between the passes (a blade that stops so is
// cut from where it came in straight to the wound: end_stem_event, systems/cut/stem_2d.h). 688 and
// 700 (and seed 1's 437): the cross-cut, after the loop, went into the freed lens where it had
// drifted over the skin (in 2D the two overlap); the blade's anchor was taken in the skin, the
// lowest element holding it, the lens slid under the start of the next quad, and its rim element's
// edge was never crossed (the anchor is taken in an element the blade has entered first: tissue_at,
// systems/cut/material_anchor.h).
TEST(StressLoops, LoopsOfAnotherSeedFreeTheirPieces) {
    expect_pieces_freed({{2, 605}, {2, 688}, {2, 700}, {1, 437}});
}

// Loops of seed 2 begun in the open wound of the cross-cut made before them. 424 and 965: the start
// lies in one lip's material, which the element's own nodes put 0.59 and 0.67 mm from the cross-cut's
// line, past the join distance (0.57 mm on 2 mm cells), and the lens half beside stayed one with the
// skin (a stem's end joins a wound within the join distance and that wound's opening there:
// end_on_wound, systems/cut/stem_2d.cpp). 628: the closing pass, through the element the loop began
// in, was taken as the loop's first line going on, which crossed the next edge 13 um from the point
// the element beside had cut through, and the wedge between joined the lens to the skin (such a
// pass is a line of its own: record_recut, systems/cut/recut.h).
TEST(StressLoops, LoopsBegunInACrossCutsOpenWoundFreeTheirPieces) { expect_pieces_freed({{2, 424}, {2, 965}, {2, 628}}); }

// A loop alone of seed 3 (593) whose closing pass runs 0.3 mm inside its first pass and stops there,
// in the element beside the one the first pass crossed: no line of its own element is near its
// end, so its stem met nothing, and the strip between the passes joined the lens to the skin. A
// blade that stops within the join distance of a wound across an edge is drawn on to it
// (wound_beside, systems/cut/stem_2d.h). Seed 2's 202 (a loop begun in a cross-cut's open wound)
// is freed by the same rule. Seed 1's 381 keeps its three pieces: its closing pass stops beside
// a wound across the edge it came in by, which it is not drawn back across.
TEST(StressLoops, ALoopThatStopsBesideItsFirstPassAcrossAnEdgeIsClosed) {
    expect_pieces_freed({{3, 593}, {2, 202}, {1, 381}});
}

// A loop whose passes miss each other in the material by less than the cutter's join distance is
// scored as closed. Trajectory 856, a loop alone: its closing pass, drawn along the same ellipse in
// space, runs beside its first pass in the material, 0.16 mm from it (that pass's wound has opened
// and the tissue has moved; docs/BENCHMARKS.md traced it from the cuts the run recorded). The
// paths alone part nothing bigger than an element from the patch; closed across the gap, they
// free the lens, and that is the count the suite expects. The cutter frees it: the closing pass
// crosses the element the loop began in, past its start, and the stretch from the start to where
// the first pass went out is cut once that element is split (stem_at_start, systems/cut/cut_system.h;
// before, the lens stayed joined through that stretch).
TEST(StressLoops, ALoopWhosePassesMissByLessThanTheJoinIsClosed) {
    std::mt19937_64 rng(1);
    for (int k = 0; k < 856; ++k) random_loop_scene(rng);
    auto sim = make_simulation(random_loop_scene(rng), false);
    ASSERT_EQ(sim->world.tools.count(), 1);
    std::vector<std::vector<Vec3>> paths;
    track_blades(sim->world, paths);
    for (int n = 0; n < static_cast<int>(std::lround(kLoopDuration / kLoopStep)); ++n) {
        step_simulation(*sim);
        track_blades(sim->world, paths);
    }
    const auto regions = [](const std::vector<std::vector<Vec3>>& cuts) {
        int count = 0;
        for (const double a : parted_regions(cuts, Vec3::Zero(), Vec3(kLoopPatch, kLoopPatch, 0.0), kLoopRaster).area)
            count += a >= 0.002 * 0.002 / 2.0;
        return count;
    };
    EXPECT_EQ(regions(paths), 1) << "the paths as they are";
    const LoopTally t = loop_pieces(sim->world, paths);
    EXPECT_GT(t.gap, 1e-4);
    EXPECT_LT(t.gap, 3e-4);
    EXPECT_EQ(t.expected, 2);
    EXPECT_EQ(t.pieces, 2) << "the lens freed";
}

}  // namespace
}  // namespace xcut
