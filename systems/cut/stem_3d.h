#pragma once
// The stem of a T in 3D (docs/xfem.md, Several cuts per element: What is built in 3D). A scalpel
// lowered into a wound and drawn away from it begins inside an element already cut: it never
// crosses that element from side to side, so the semi-progressive rule (split once fully crossed)
// would leave the element whole along the stem, a bridge of tissue one element long between the
// wound and the stem. Here the blade's edge where it began is kept (BladeCut::began_in); once the
// blade has crossed every edge of the element that its plane crosses ahead of that edge, the
// element is cut again along that plane, bounded to the part ahead (CutEvent::bounded): of its
// fragments, those whose section by the plane lies ahead of the start are divided, those behind it
// (across the wound) are not. A stem drawn to a wound and ended there is cut the same way behind the
// blade's last edge inside the element, once the blade has left it. 2D's form is stem_event
// (systems/cut/stem_2d.h).
#include <array>
#include <vector>

#include "components/cut_state.h"
#include "engine/world.h"

namespace xcut {

/// Tolerance [-] of a stem's start, as a fraction of the element's longest edge: a fragment whose
/// section reaches this far behind the blade's first edge is still ahead of it (a blade lowered
/// into an open wound begins between its lips, which the rest configuration puts on the wound's
/// plane to within the tissue's motion since), and the plane's crossings of edges within it of the
/// start need not be crossed by the blade.
inline constexpr double kStemStartFraction = 0.1;

/// Notes in bc.began_in the elements already cut (3D, where elements are cut again) that the line
/// of quad q's first edge passes through, a blade length beyond either end (a blade lowered along
/// its edge sweeps nothing, so its first quad begins higher than it reached), when the blade cut
/// nothing before q (bc's front and partly crossed elements empty: it was lowered into the tissue
/// there). `candidates`: the elements q may reach.
void note_stem_starts(const World& world, BladeCut& bc, const CutQuad& q, const std::vector<int>& candidates);

/// The event cutting element e (already cut, 3D) again along the plane the blade sweeps from the
/// edge where it began inside e (`start`: tip, heel, current positions [m]) toward its tip now
/// (`tip`), bounded to the part ahead of that edge, once the blade has crossed (c) every edge of
/// e that plane crosses more than kStemStartFraction ahead of it. Its levels are at rest, by the
/// field of the material ahead of the start; where it crosses an edge within kStemStartFraction of
/// where e's cut does, it crosses there. False while the blade has not, or if the plane is degenerate.
bool stem_event_3d(const World& world, int e, const std::array<Vec3, 2>& start, const Vec3& tip,
                   const ElementCrossings& c, CutEvent& ev);

/// Notes in bc.ended_in quad q's last edge for each element already cut that the blade is partly
/// through (bc.crossing; 3D, where elements are cut again) and that the edge's line, a blade length
/// beyond either end, passes through.
void note_stem_ends(const World& world, BladeCut& bc, const CutQuad& q);

/// Queues (world.pending_cuts) the events cutting each element already cut that the blade of `tool`
/// leaves partly crossed (`leaving`, in bc.crossing), behind the edge where it ended inside it
/// (bc.ended_in): stem_event_3d the other way, its start that edge and its part the one behind it.
/// A stem drawn to a wound and ended at it (or a little short of it, within kStemStartFraction)
/// reaches it. Returns how many.
int end_stems_3d(World& world, BladeCut& bc, const std::vector<int>& leaving, int tool);

/// Whether a bounded 3D event (stem_event_3d) divides a fragment whose section by its plane has
/// the rest points `section`: every one lies ahead of the stem's start (within kStemStartFraction
/// of `size`, the element's longest edge [m]).
bool stem_covers(const CutEvent& ev, const std::vector<Vec3>& section, double size);

}  // namespace xcut
