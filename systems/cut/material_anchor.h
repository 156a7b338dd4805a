#pragma once
// The blade's anchor as a point of the tissue (CutState::anchor_material). A collision quad runs
// from the blade's edge at the last quad to its edge now (paper §3.3, Fig. 14), and each quad is
// tested against the tissue where it is at its own step. Kept as a point in space, the anchor lets
// the tissue slide past it between quads: what moved across it in the meantime is never swept (a
// gap: an edge that slid past the quad's start is crossed by neither quad), or is swept twice. So
// the anchor is the tissue the blade's edge was in: the next quad starts where that tissue is now,
// and the quads' path through the tissue is continuous, as the blade's is. An end of the edge
// outside the tissue (the heel of a 2D blade, out of the plane) moves as the other end does, or,
// with neither end in tissue, stays where it was. An end in an element already cut is carried by
// the fragment whose material it is (its node copies): a blade crossing a lens its loop has freed,
// which drifts, or a cross-cut's wound that opens, missed an edge 0.1 mm from a node with the anchor
// left in space there (loop stress trajectories 399 and 301, docs/BENCHMARKS.md).
//
// 2D only. A scalpel drawn round 36 ellipses in the face skin (tests/systems/test_recut_loops.cpp)
// left 5 lenses joined to the skin with the anchor in space, 2 with it in the tissue. In 3D the same
// rule (a tet's barycentric coordinates; a heel above the skin moved as the tip) changed no bridge
// the stress suite counts (`xcut stress --count 100`: 255 elements crossed through left joined,
// 258 with it) and left more open surface edges where scalpels cut again (`--blades 4 --recut
// --count 1000`: 1,322 in 78 runs, 1,531 in 91 with it), so 3D keeps the paper's anchor in space.
#include "engine/world.h"
#include "systems/kernels/element_bvh.h"

namespace xcut {

/// The tissue at each end of a blade's edge (2D): for each, the lowest mesh triangle whose
/// material holds it, in its plane, with its barycentric coordinates (lowest: the choice is
/// deterministic): a whole one (not cut, nor queued) by its current shape; one cut, where elements
/// are cut again (recut_allowed), by the first of its fragments whose node copies' current triangle
/// holds it with the fragment's own material there (MaterialPoint::fragment). Element -1 if none,
/// and in 3D. Where two materials hold it (a freed piece drifted over the tissue it was cut from:
/// in 2D they overlap), one that `entered` (the blade's partly crossed elements) holds comes first:
/// the blade went into that element's material and has not left it. Taken in the other, the anchor
/// moved with it, the piece slid under the blade's next quad, and the cross-cut through a freed lens
/// missed its rim element's edge (loop stress seed 2, trajectory 700).
std::array<MaterialPoint, 2> tissue_at(const World& w, ElementBvh& bvh, const Vec3& tip, const Vec3& heel,
                                       const BladeCut* entered = nullptr);

/// The tissue at p (current, 2D) in mesh triangle e: the whole triangle's, by its current shape, or,
/// where e is cut and cut again in this world (recut_allowed), the first of its fragments whose node
/// copies' current triangle holds p with the fragment's own material there. Element -1 if none (also
/// for an element queued to split this step).
MaterialPoint material_in(const World& w, int e, const Vec3& p);

/// Where material point m (2D) is now [m]: its element's, or its fragment's node copies', current
/// positions at its barycentric coordinates.
Vec3 material_position(const World& w, const MaterialPoint& m);

/// Where material point m (2D) lies at rest [m]: its element's rest corners at its barycentric
/// coordinates (a fragment's node copies share their element's rest corners).
Vec3 material_rest(const World& w, const MaterialPoint& m);

/// Moves tool i's anchor (tip, heel) to where the tissue it was in is now, while that element is
/// still whole (or its fragment still holds it): an end in tissue moves with it, an end outside by
/// the other end's displacement.
void carry_anchor(World& w, int i);

}  // namespace xcut
