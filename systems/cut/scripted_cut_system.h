#pragma once
// ScriptedCutSystem: the programmatic cutter. At its time, a scripted cut (a planar polygon in 3D,
// a segment in 2D, in the current configuration, or at rest: drawn on the body) queues a split for every element it crosses
// completely: every edge whose ends lie on opposite sides of the polygon's plane must cross it
// inside the polygon. An element the polygon only enters stays whole: it is the crack front.
#include <vector>

#include "engine/scheduler.h"
#include "engine/world.h"

namespace xcut {

/// Queues (into world.pending_cuts) the splits for one polygon. Returns how many were queued.
/// `progressive`: an element the polygon enters but does not cross completely is split too, as a
/// progressive front's tip element (CutEvent::crossed: the edges crossed inside the polygon; the
/// enrichment holds the nodes of its other split edges, docs/xfem.md). `at_rest`: the polygon is
/// drawn on the body at rest (ScriptedCut::at_rest), and the elements it crosses are found there.
int queue_polygon_cut(World& world, const std::vector<Vec3>& polygon, bool progressive = false, bool at_rest = false);

SystemDesc scripted_cut_system();

}  // namespace xcut
