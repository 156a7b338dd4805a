#pragma once
// A blade lying on the skin (docs/xfem.md, A blade lying on the skin): a split that would leave a
// flap thinner than kThinFlapFraction of its element over a face of the body is not made.
#include "engine/world.h"

namespace xcut {

/// Whether the split `ev` of element e (current positions) lies on the skin: every point of the cut
/// is closer than kThinFlapFraction of e's shortest edge to the plane of one face of e that no other
/// element holds (2D: the line of a boundary edge), and one of them is farther than that from every
/// node of e. Such a cut would leave a flap thinner than that over the face: it is the blade lying on
/// the surface, not an incision. (A cut whose points all lie at nodes is one through or beside a node
/// layer, which cuts the body: the slivers of docs/xfem.md.)
bool lies_on_skin(const World& w, int e, const CutEvent& ev);

}  // namespace xcut
