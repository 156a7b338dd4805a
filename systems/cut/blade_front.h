#pragma once
// Where a blade's edge lies in 3D tissue, as a straight crack front in the rest configuration
// (scene cutter.tip on a 3D mesh; systems/cut/crack_tip_system.h, follow_blades). The front's
// enrichment (enrich_crack_front) takes a straight front that crosses its zone whole: a blade whose
// edge runs through the tissue from one face to another (a scalpel through a skin's thickness, a
// blade pushed down through a block's width) carries one; an edge that ends inside the tissue (a
// front with a corner: along the edge, then along the path of its deep end) does not.
#include "engine/world.h"

namespace xcut {

/// What a blade's edge holds: no front (not in the tissue, or in its own wound: the middle of its
/// stretch in the tissue lies in an element already cut), a front, or an edge that ends inside the
/// tissue or crosses it more than once (no straight front through its zone).
enum class BladeFront { kNone, kFront, kNotThrough };

/// Tool t's edge (tip to heel, current coordinates) clipped to the live tetrahedra it passes
/// through. With a front: `point` is the rest point of the middle of its stretch in the tissue
/// (mapped through the uncut element holding it), `tangent` the unit rest direction from where it
/// enters to where it leaves (each end mapped through its own element) [m, -].
BladeFront blade_rest_front(const World& world, int t, Vec3& point, Vec3& tangent);

/// Whether the rest line through `point` along unit `tangent` runs through a live mesh element (one
/// not yet split): a front a blade keeps while it stands lies in tissue the cut has since split
/// when the split caught up with it.
bool front_in_uncut_tissue(const World& world, const Vec3& point, const Vec3& tangent);

}  // namespace xcut
