#pragma once
// `xcut stress --loops` (docs/verification.md problem 8, closed loops): a scalpel drawn round a
// random ellipse in a 2D skin patch, with a straight cross-cut through its lens before or after the
// loop in two runs of three; the pieces the cuts free are checked against the regions the paths
// enclose, computed in closed form (the ellipse's area, and the two segments a chord divides it
// into), not by the cutter. A cross-cut after the loop goes through a lens that is free and moves:
// its segments are those of the path the blade took through the lens's material (the lens's nodes'
// motion, not the cutter, says where that is).
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

/// The regions a loop trajectory's paths enclose, besides the patch around them: their rest areas
/// [m^2] (the drawn ellipse's, or its two segments', less the patch's stretch: the paths are drawn
/// on the skin stretched 2.5 % each way by its borders) and the length of their boundaries [m].
struct LoopRegions {
    std::vector<double> area, perimeter;
    /// A cross-cut after the loop: the lens is free then, and it drifts and turns as it relaxes
    /// (1-2 mm and 5-10 degrees while the cross-cut goes through it, on trajectories 119 and 237),
    /// so the chord the blade cuts through its material is not the drawn one. Its regions are then
    /// taken from the blade's path through the lens's material (track_cross_cut) instead.
    bool cross_after_loop = false;
    Vec3 centre = Vec3::Zero();  ///< the drawn ellipse at rest: centre [m], major axis's angle, semi-axes [m]
    double angle = 0.0, a = 0.0, b = 0.0;
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
};

/// A freed piece's area may differ from its region's by this much per metre of the region's
/// boundary [m]: the tissue's motion under the blade (the wound opens behind it, the skin
/// retracts) and the cut's straight line through each element.
constexpr double kLoopAreaTolerance = 0.0005;

/// After a step of a cross-cut made after the loop: the cross-cut blade's point pulled back to rest
/// through the lens's motion (the affine map that best takes the rest positions of the mesh nodes
/// well inside the drawn ellipse to where they are now: the lens's drift, turn and relaxation, not
/// anything the cutter decided), appended to `path` while the blade is within the ellipse's
/// neighbourhood. Nothing otherwise.
void track_cross_cut(const World& w, const LoopRegions& regions, std::vector<Vec3>& path);

/// The regions the ellipse at rest is divided into by `path` (rest points; from its first entry
/// into the ellipse to its last exit): each one's area and boundary, as LoopRegions holds them.
/// False if the path does not cross the ellipse.
bool path_regions(const LoopRegions& ellipse, const std::vector<Vec3>& path, LoopRegions& out);

/// The pieces of `w` (counted again) against `regions` (a cross-cut after the loop: against the
/// regions of its tracked `path`, when it crossed the lens).
LoopTally loop_pieces(World& w, const LoopRegions& regions, const std::vector<Vec3>& path = {});

}  // namespace xcut
