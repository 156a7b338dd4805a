#pragma once
// ScriptedFrontSystem: the crack front a scripted cut leaves in the tissue, enriched with the branch
// functions (systems/cut/crack_tip_system.h) when the cut asks for it (ScriptedCut::front_radius,
// the scene's "cuts[i].front"). The semi-progressive cut splits the elements the polygon crosses
// whole and leaves the ones it only enters: the front's functions carry the crack into those, to
// where the polygon ends, and the near-front √r field around it.
#include <vector>

#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// A crack front at rest: a point on it, the crack's direction there (unit, ahead of the crack,
/// away from the cut) and the front's unit tangent (2D: z) [m, -].
struct CutFront {
    Vec3 point = Vec3::Zero();
    Vec3 direction = Vec3::UnitX();
    Vec3 tangent = Vec3::UnitZ();
};

/// The fronts where the polygon (rest configuration) ends inside the world's tissue at rest. 3D: the
/// one polygon edge whose line runs through the tissue, which it must cross whole (a straight front:
/// the line runs through no element beyond the edge's ends); its direction is the polygon's outward
/// normal in its plane. 2D: each end of the segment that lies inside an element. Throws
/// std::invalid_argument saying what is wrong when no edge or end lies in the tissue, two edges do
/// (a front with corners), or the edge ends inside the tissue.
std::vector<CutFront> scripted_cut_fronts(const World& world, const std::vector<Vec3>& polygon);

/// Enriches the fronts of the scripted cuts applied so far that ask for one (after the
/// EnrichmentSystem has split their elements), each over its radius, and builds every front's zone
/// again when an element cut since shares a node with a zone's element (a later cut through a zone:
/// its integrals follow the new parts; a split elsewhere, a scalpel's away from the fronts, leaves
/// the zones as they are and costs no integral). Returns whether it built the zones. A front the enrichment refuses throws
/// std::invalid_argument naming the cut ("cuts[i].front: ...").
bool enrich_scripted_fronts(World& world);

/// Whether a scripted cut of the world asks for its front to be enriched.
bool has_scripted_fronts(const World& world);

/// The ScriptedFrontSystem: enrich_scripted_fronts each step, after the EnrichmentSystem.
SystemDesc scripted_front_system();

}  // namespace xcut
