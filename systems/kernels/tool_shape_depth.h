#pragma once
// Penetration of a point into a tool's contact shape, in the tool's frame: depth > 0 inside, with
// the unit normal pointing out of the tool (the direction that frees the point fastest).
//  - sphere, capsule (axis along z, centred): exact;
//  - box (centred, axis-aligned in the tool frame): the nearest face;
//  - closed mesh: inside by the generalized winding number (> 1/2), depth and normal to the
//    nearest point of the nearest triangle.
#include "components/tools.h"

namespace xcut {

struct Penetration {
    double depth = 0.0;          ///< [m]; <= 0: outside
    Vec3 normal = Vec3::UnitZ(); ///< unit, tool frame
};

Penetration penetration(const ToolShape& shape, const Vec3& q);

}  // namespace xcut
