#pragma once
// The stem of a T in 2D (docs/xfem.md, Several cuts per element): a scalpel that begins inside an
// element already cut, or stops inside one it came into, never crosses it from side to side, so the
// semi-progressive rule (split once fully crossed) would leave the element whole along the stem, a
// bridge one element long between the wound and the blade. The element is cut again along the
// blade's segment inside it, bounded by it (CutEvent::bounded), its end met with the element's wound
// within the join distance. 3D's form is systems/cut/stem_3d.h.
#include "components/cut_state.h"
#include "engine/world.h"

namespace xcut {

/// A scalpel that starts inside cut element e (2D; its swept segment from `start`, current
/// positions) and crosses one of its edges, `crossed` (local edge) at parameter t: the event cutting
/// e again along that segment, bounded by it (the stem of a T begun at the wound divides the
/// fragment between the wound and that edge). A start a hair short of one of e's lines (on the
/// crossed edge's side, within kJoinFraction of e's longest edge) is moved onto it: a blade that
/// stops just short of its own wound, where the tissue moved under it, meets it. False if `start`
/// is not inside e.
bool stem_event(const World& world, int e, int crossed, double t, const Vec3& start, CutEvent& ev);

/// stem_event for a blade that ended at `end` (current) after coming in to cut element e across
/// local edge `crossed` at t, or, where that gives none because the blade went back out across that
/// edge (it dipped into e's corner and stopped beyond), from its crossing straight to the nearest
/// point of the line of the fragment it came in to that it ended within kJoinFraction of e's longest
/// edge of: a loop's closing pass that ran beside its first pass, dipping in and out of the element
/// that pass crossed, and stopped there (loop stress seed 2, trajectory 605).
bool end_stem_event(const World& world, int e, int crossed, double t, const Vec3& end, CutEvent& ev);

/// A blade that stopped at material point `end` (2D) beside a wound it never met: the nearest point
/// of a line of a cut element across an edge of end's element, within kJoinFraction of that
/// element's longest edge of end's rest point (nearer than any line of end's own element, which
/// its stem meets: end_on_wound), through that edge, as a position now (the node copies of the
/// fragment on end's side of the line). Not through an edge the blade came into the element by
/// (`entered`, local edges' bits: drawn back out there it would dip, and a loop's closing pass that
/// came in across its own first pass met it already; seed 1, trajectory 381). The blade is then
/// drawn on to it, so its wound meets the other across the gap: a loop whose closing pass runs
/// beside its first pass, 0.3 mm inside it on 2 mm cells, and stops there, in the element beside
/// the one the first pass crossed (loop stress seed 3, trajectory 593). False if none.
bool wound_beside(const World& world, const MaterialPoint& end, uint8_t entered, Vec3& to);

/// Queues the stem event (stem_event; end_stem_event where the blade `ended` at `start`) of blade
/// `tool` in cut element e, crossed once (`c`: its one crossed edge), from `start` (current
/// position: where the blade stopped, or turned in a dip). False if there is none.
bool queue_stem(World& world, int e, const ElementCrossings& c, const Vec3& start, int tool, bool ended = false);

}  // namespace xcut
