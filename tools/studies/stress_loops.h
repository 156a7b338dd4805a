#pragma once
// `xcut stress --loops` (docs/verification.md problem 8, closed loops): a scalpel drawn round a
// random ellipse in a 2D skin patch, with a straight cross-cut through its lens before or after the
// loop in two runs of three; the pieces the cuts free are checked against the regions the blades'
// paths through the material enclose (tools/studies/parted_regions.h), not against what the cutter
// recorded. The paths are drawn in space, and the tissue moves under them: a wound opens behind the
// blade, a freed lens drifts and turns, so a loop drawn closed in space ends 0.001-0.4 mm beside its
// first pass in the material in most runs, and a cross-cut after the loop cuts the lens along a chord
// turned 5-10 degrees from the drawn one (trajectories 119, 237). Each blade's point is pulled back
// to rest at every step through the tissue that holds it (track_blades).
#include <random>
#include <vector>

#include "engine/io/scene.h"

namespace xcut {

struct World;

/// Simulated time of a loop trajectory [s] and its step [s]: the loop from 0.2 to 2.2 s, the
/// cross-cut from 2.4 to 3.0 s (or from 0 to 0.6 s, before the loop starts at 0.8 s).
constexpr double kLoopDuration = 3.2;
constexpr double kLoopStep = 0.01;
constexpr double kLoopPatch = 0.04;   ///< the skin patch's side [m]
constexpr double kLoopPull = 0.0005;  ///< each of its borders drawn outward by [m]
/// The patch's stretch each way [-], uniform away from the cuts: a drawn length is this times its rest one.
constexpr double kLoopStretch = 1.0 + 2.0 * kLoopPull / kLoopPatch;

/// The regions a loop trajectory's paths enclose as drawn, besides the patch around them: their rest
/// areas [m^2] (the drawn ellipse's, or its two segments', less the patch's stretch: the paths are
/// drawn on the skin stretched 2.5 % each way by its borders) and the length of their boundaries [m].
/// Closed forms, against which the raster of parted_regions is checked; the suite scores the
/// pieces against the paths through the material.
struct LoopRegions {
    std::vector<double> area, perimeter;
};

/// The next loop trajectory of `rng`: a 40 x 40 mm skin patch (2 mm cells, 2 mm thick, E 1e4 Pa),
/// its four borders drawn 0.5 mm outward (skin under tension, as scenes/excision_2d.json) and no
/// gravity; a scalpel round an ellipse of semi-axes 6-13 x 4-9 mm at a random angle, centre and
/// start, either way round, 0.4 rad past its start; a second scalpel's straight cut through the
/// lens (a chord at most half the way to its rim from the centre, in the ellipse's unit-circle
/// frame), 3 mm past the rim at both ends, after the loop or before it. `regions` gets what they
/// enclose.
Scene random_loop_scene(std::mt19937_64& rng, LoopRegions* regions = nullptr);

/// What the cuts freed, against the regions: the pieces of at least one element's area (the patch
/// and each region's), and the strips, pieces smaller than an element (between two passes of a
/// blade a fraction of a cell apart: docs/xfem.md).
struct LoopTally {
    int expected = 0;  ///< pieces the paths make: the patch and the regions
    int pieces = 0;    ///< pieces of at least one element's area
    int strips = 0;    ///< pieces smaller than that
    /// 1 if the pieces do not match the regions: another count, or a region whose piece's area is
    /// off by more than kLoopAreaTolerance times its perimeter
    int mismatch = 0;
    /// With the right count, the largest |piece's area - region's| over a region's boundary [m]
    double offset = 0.0;
    /// The loop's path through the material: how near its end comes back to its start [m]
    /// (closest_return: 0 where it crosses it). Within kLoopJoin the loop is taken as closed.
    double gap = 0.0;
};

/// A loop whose end passes this near its start in the material [m] is closed: the cutter moves a
/// crossing within kJoinFraction (systems/cut/recut.h) of an element's longest edge (the patch's
/// 2 mm cells' diagonal) of an earlier one onto it, so that a scalpel closing a loop meets its own
/// wound where the tissue has moved since. In 915 of the first 1,000 trajectories the loop's end
/// passes its start 0.001-0.38 mm apart in the material without crossing it, and the cutter freed
/// the lens in all but one (docs/BENCHMARKS.md).
constexpr double kLoopJoin = 0.2 * 0.002 * 1.4142135623730951;

/// The raster's cells for the regions [m] (a 40 mm patch: 2000 x 2000).
constexpr double kLoopRaster = 2e-5;

/// A freed piece's area may differ from its region's by this much per metre of the region's
/// boundary [m]: the tissue's motion under the blade (the wound opens behind it, the skin
/// retracts) and the cut's straight line through each element.
constexpr double kLoopAreaTolerance = 0.0005;

/// How far from the material a blade in an open wound is followed along its lip [m].
constexpr double kLoopWoundReach = 0.001;

/// After a step: each bladed tool's point pulled back to rest through the tissue that holds it
/// now, appended to paths[tool] (resized to the tools): the first mesh triangle whose material
/// holds it, a whole one by its current shape, a cut one by the fragment whose node copies' current
/// triangle holds it with its own material there (material_in, systems/cut/material_anchor.h). A
/// blade in an open wound, which no material holds, is at the wound's lip in the material: the
/// rest point of the nearest material within kLoopWoundReach (a blade that runs into a wound has
/// met it; one that runs along its own open wound, as a loop's overshoot does, follows its first
/// pass). Off the patch it adds nothing.
void track_blades(const World& w, std::vector<std::vector<Vec3>>& paths);

/// The pieces of `w` (counted again) against the regions the blades' `paths` (rest) part the patch
/// into, the loop's (path 0) closed across its gap where that is within kLoopJoin.
LoopTally loop_pieces(World& w, const std::vector<std::vector<Vec3>>& paths);

}  // namespace xcut
