#pragma once
// The regions of a rectangle that cut paths part (rest configuration, the xy plane), for the loop
// stress suite's reference (tools/studies/stress_loops.h): what the blades' paths through the
// material enclose, whatever their shape, computed without the cutter.
//
// A raster of square cells: two neighbouring cells are one material unless a path crosses the
// segment between their centres (each path segment blocks exactly the connections it crosses, the
// scan-line rule of polygon fill: a vertex on a row of centres counts on one side only, so two
// segments meeting there block it once). The regions are the connected sets of cells (flood fill).
// A region's area is its cells' (error about half a cell times its boundary), its boundary the
// length of the paths' segments with another region across them (a segment with the same region on
// both sides, a path's loose end, bounds nothing).
#include <vector>

#include "components/nodes.h"

namespace xcut {

struct PartedRegions {
    std::vector<double> area;      ///< per region [m^2]
    std::vector<double> boundary;  ///< per region: the length of cut path that bounds it [m]
};

/// The regions of the rectangle [lo, hi] (xy) the polylines `paths` part, on cells of side `cell`
/// [m]. std::invalid_argument if the raster would exceed 2^24 cells.
PartedRegions parted_regions(const std::vector<std::vector<Vec3>>& paths, const Vec3& lo, const Vec3& hi, double cell);

/// The point of segment ab nearest to p (xy).
Vec3 nearest_on(const Vec3& a, const Vec3& b, const Vec3& p);

/// The closest approach between the start of polyline p and its end: over pairs of segments more
/// than half its length apart along it (arc length), the least distance between them [m] (0 where
/// they cross), and the two points that realise it (`from` on the earlier segment). +inf if there
/// is no such pair. A loop whose end crosses its start closes; one whose end passes beside it, at
/// this distance, does not.
double closest_return(const std::vector<Vec3>& p, Vec3& from, Vec3& to);

}  // namespace xcut
