#pragma once
// PiecesSystem: counts the pieces of tissue after the cutter has applied the step's splits, and
// logs each piece a cut frees (components/pieces.h). It counts again only in a step that changed
// the topology (a split, a released crack-front node, a snapping copy), so an uncut step pays one
// comparison. Both cutters are counted the same way: the force elements that carry volume, joined
// through the DOF nodes they share (union-find, Tarjan 1975, in element order: deterministic).
#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// Counts the pieces of `world` now; returns true when the topology changed since the last count
/// (and so the pieces were counted again). New pieces are appended to world.pieces.log.
bool count_pieces(World& world);

/// The end of the run's line on the pieces cuts made ("" when they made none).
std::string pieces_report(const World& world);

SystemDesc pieces_system();

}  // namespace xcut
